// `aoeval bench gtao` (see bench_gtao.h).
#include "harness/bench/bench_gtao.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "harness/cli/commands.h"
#include "corpus.h"
#include "errors.h"
#include "estimators/gtao/gtao.h"
#include "estimators/gtao/gtao_vulkan.h"
#include "estimators/registry.h"
#include "estimators/vulkan/vk_context.h"
#include "harness/evaluation/evaluation.h"
#include "harness/results/results_store.h"
#include "version.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::map<std::string, double> medians(const std::vector<std::map<std::string, double>>& runs) {
  std::map<std::string, std::vector<double>> values;
  for (const auto& run : runs)
    for (const auto& [key, ms] : run) values[key].push_back(ms);
  std::map<std::string, double> out;
  for (const auto& [key, v] : values) out[key] = median(v);
  return out;
}

double at(const std::map<std::string, double>& m, const std::string& key) {
  const auto it = m.find(key);
  return it == m.end() ? 0.0 : it->second;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

ResultRow timing_row(const RunContext& context, const EstimatorInfo& e, const ParamSet& params,
                     const nlohmann::json& overrides, const Scene& scene, const View& view, int w,
                     int h, const std::vector<double>& totals,
                     const std::map<std::string, double>& passes, const std::string& device) {
  ResultRow row;
  row.run_id = context.run_id;
  row.run_name = run_name(e, params, overrides, scene.name, view.name, w, h);
  row.estimator = e.name;
  row.params = params.json();
  row.scene = scene.name;
  row.view = view.name;
  row.width = w;
  row.height = h;
  row.definition = e.definition(params).to_json().dump();
  row.backend = backend_name(e.backend);
  row.time_ms_median = median(totals);
  row.time_ms_min = *std::min_element(totals.begin(), totals.end());
  row.time_ms_max = *std::max_element(totals.begin(), totals.end());
  row.repetitions = static_cast<int>(totals.size());
  row.time_ms_samples = totals;
  for (const auto& [pass, ms] : passes)
    if (pass != "total_ms") row.pass_ms[pass] = ms;
  row.machine = context.machine;
  row.device = device;
  row.git_commit = context.git_commit;
  row.aoeval_version = kAoevalVersion;
  row.timestamp = context.started;
  row.status = "timing only";
  return row;
}

}  // namespace

void bench_gtao(const GtaoBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  const EstimatorInfo& gpu_info = find_estimator("gtao");
  const EstimatorInfo& cpu_info = find_estimator("gtao-cpu");
  const nlohmann::json overrides = parse_set_arguments(o.sets);
  const ParamSet gpu_params = resolve_params(gpu_info.name, gpu_info.params, overrides, "--set");
  nlohmann::json cpu_overrides = overrides;
  cpu_overrides.erase("gbuffer");
  const ParamSet cpu_params =
      resolve_params(cpu_info.name, cpu_info.params, cpu_overrides, "--set");
  const GtaoSettings s = gtao_settings_of(cpu_params);
  const bool raster = gpu_params.choice("gbuffer") == "raster";

  Scene scene = load_scene(o.scene);
  const View& view = scene.view(o.view);
  EmbreeScene embree(scene);
  const Camera camera = make_camera(view, w, h);
  const GBuffer g = render_gbuffer(embree, camera);

  std::string reason;
  vk::Context* vk = vk::shared_context(&reason);
  if (!vk) {
    std::printf("bench gtao: skipped: no Vulkan device (%s)\n", reason.c_str());
    return;
  }

  std::unique_ptr<GtaoDevice> device =
      raster ? std::make_unique<GtaoDevice>(*vk, s, scene, camera)
             : std::make_unique<GtaoDevice>(*vk, s, hbao_frame_from_gbuffer(g), camera);
  const GtaoOutput first = device->run();
  const HbaoFrame frame = device->frame();
  const GtaoOutput twin = gtao_cpu(frame, camera, s);
  double ao_diff = 0.0, bent_diff = 0.0;
  size_t covered = 0, not_identical = 0;
  for (size_t k = 0; k < frame.depth.size(); ++k) {
    if (!(frame.depth[k] > 0.0f)) continue;
    ++covered;
    ao_diff = std::max(ao_diff, std::abs(static_cast<double>(first.ao[k]) - twin.ao[k]));
    bool same = first.ao[k] == twin.ao[k];
    if (s.bent) {
      bent_diff =
          std::max(bent_diff, static_cast<double>(glm::length(first.bent[k] - twin.bent[k])));
      same = same && first.bent[k] == twin.bent[k];
    }
    not_identical += same ? 0 : 1;
  }

  for (int i = 0; i < o.warmup; ++i) device->run();
  std::vector<std::map<std::string, double>> gpu_runs;
  std::vector<double> gpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const GtaoOutput r = device->run();
    gpu_runs.push_back(r.pass_ms);
    gpu_totals.push_back(at(r.pass_ms, "total_ms"));
  }
  for (int i = 0; i < o.warmup; ++i) gtao_cpu(frame, camera, s);
  std::vector<std::map<std::string, double>> cpu_runs;
  std::vector<double> cpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const GtaoOutput r = gtao_cpu(frame, camera, s);
    cpu_runs.push_back(r.pass_ms);
    cpu_totals.push_back(at(r.pass_ms, "horizon_ms") + at(r.pass_ms, "denoise_ms"));
  }
  const std::map<std::string, double> gpu = medians(gpu_runs), cpu = medians(cpu_runs);
  const double cpu_total = median(cpu_totals);
  const double gpu_ao_ms = at(gpu, "horizon_ms") + at(gpu, "denoise_ms");
  const double samples = static_cast<double>(covered) * s.slices * 2.0 * s.steps;
  const double sample_rate = samples / (at(gpu, "horizon_ms") * 1e-3);

  nlohmann::json j = {
      {"scene", scene.name},
      {"view", view.name},
      {"width", w},
      {"height", h},
      {"params", gpu_params.json()},
      {"device", vk->device_description()},
      {"cpu_threads",
       tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)},
      {"repetitions", o.repetitions},
      {"gpu_pass_ms", gpu},
      {"cpu_pass_ms", cpu},
      {"cpu_total_ms", cpu_total},
      {"gpu_ao_ms", gpu_ao_ms},
      {"speedup_gpu_over_cpu", cpu_total / gpu_ao_ms},
      {"covered_pixels", covered},
      {"horizon_samples", samples},
      {"horizon_samples_per_s", sample_rate},
      {"depth_fetches_per_s", 4.0 * sample_rate},
      {"twin_max_abs_difference", ao_diff},
      {"twin_bent_max_difference", bent_diff},
      {"twin_pixels_not_bit_identical", not_identical},
  };
  j["geometry_note"] = raster ? "gbuffer=raster: geometry_ms = raster pass + eye-space normals"
                              : "gbuffer=embree: no geometry_ms (uploaded once, outside the frame)";

  std::ostringstream md;
  md << "# gtao bench: " << scene.name << "/" << view.name << " " << w << "x" << h << "\n\n"
     << "device: " << vk->device_description() << "; parameters: " << gpu_params.json().dump()
     << "\n\n| pass | GPU ms (median of " << o.repetitions
     << ") | CPU twin ms |\n|---|---:|---:|\n";
  for (const char* pass : {"geometry_ms", "horizon_ms", "denoise_ms"}) {
    const bool has_gpu = gpu.count(pass) > 0, has_cpu = cpu.count(pass) > 0;
    md << "| " << pass << " | " << (has_gpu ? fmt("%.3f", at(gpu, pass)) : "-") << " | "
       << (has_cpu ? fmt("%.3f", at(cpu, pass)) : "-") << " |\n";
  }
  md << "| total | " << fmt("%.3f", at(gpu, "total_ms")) << " | " << fmt("%.3f", cpu_total)
     << " |\n\n"
     << "- AO passes, CPU twin / GPU: " << fmt("%.2fx", cpu_total / gpu_ao_ms) << "\n"
     << "- horizon samples: " << fmt("%.0f", samples) << " (" << s.slices << " slices x 2 x "
     << s.steps << " steps x " << covered << " covered pixels), " << fmt("%.1f", sample_rate * 1e-6)
     << " Msample/s, " << fmt("%.1f", 4.0 * sample_rate * 1e-6) << " M depth fetches/s\n"
     << "- twins: max |CPU - GPU| AO " << fmt("%.3g", ao_diff) << ", bent "
     << fmt("%.3g", bent_diff) << "; " << not_identical << " of " << covered
     << " covered pixels not bit-identical\n"
     << "- " << j["geometry_note"].get<std::string>() << "\n";
  std::printf("%s", md.str().c_str());

  const RunContext context = make_run_context("bench gtao");
  ResultsFolder folder(o.out_dir, context);
  SqliteStore store(o.database);
  store.add_run(context);
  const ResultRow gpu_row = timing_row(context, gpu_info, gpu_params, overrides, scene, view, w, h,
                                       gpu_totals, gpu, vk->device_description());
  const ResultRow cpu_row = timing_row(context, cpu_info, cpu_params, cpu_overrides, scene, view, w,
                                       h, cpu_totals, cpu, context.device);
  for (const ResultRow& row : {gpu_row, cpu_row}) {
    folder.add(row);
    store.add(row);
  }
  write_text((fs::path(o.out_dir) / "bench_gtao.json").string(), j.dump(2) + "\n");
  write_text((fs::path(o.out_dir) / "bench_gtao.md").string(), md.str());
  std::printf("%s\n%s\n", (fs::path(o.out_dir) / "bench_gtao.json").string().c_str(),
              (fs::path(o.out_dir) / "bench_gtao.md").string().c_str());
}

}  // namespace aoeval
