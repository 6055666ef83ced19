// `aoeval bench hbao`: fetch efficiency of hbao-split against a bare fetch loop, and the Vulkan
// twin against the CPU twin on the same G-buffer (see bench_hbao.h).
#include "harness/bench/bench_hbao.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "corpus.h"
#include "errors.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/registry.h"
#include "estimators/vulkan/vk_context.h"
#include "harness/cli/commands.h"
#include "harness/evaluation/evaluation.h"
#include "harness/results/results_store.h"
#include "harness/results/summary.h"
#include "version.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// Medians per key over repetitions of pass-time maps.
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

// The mean screen-space length of one step R / Ns at the covered pixels' depths, pixels.
double mean_step_pixels(const HbaoFrame& f, const HbaoSettings& s) {
  const double step = s.radius / s.steps;
  double sum = 0.0;
  size_t n = 0;
  for (float z : f.depth) {
    if (!(z > 0.0f)) continue;
    sum += step * f.focal / z;
    ++n;
  }
  return n ? sum / static_cast<double>(n) : 1.0;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

ResultRow timing_row(const RunContext& context, const EstimatorInfo& e, const ParamSet& params,
                     const nlohmann::json& overrides, const Scene& scene, const View& view,
                     const GBuffer& g, const std::vector<double>& totals,
                     const std::map<std::string, double>& passes, const std::string& device) {
  ResultRow row;
  row.run_id = context.run_id;
  row.run_name = run_name(e, params, overrides, scene.name, view.name, g.width, g.height);
  row.estimator = e.name;
  row.params = params.json();
  row.scene = scene.name;
  row.view = view.name;
  row.width = g.width;
  row.height = g.height;
  row.definition = e.definition(params).to_json().dump();
  row.backend = backend_name(e.backend);
  row.time_ms_median = median(totals);
  row.time_ms_min = *std::min_element(totals.begin(), totals.end());
  row.time_ms_max = *std::max_element(totals.begin(), totals.end());
  row.repetitions = static_cast<int>(totals.size());
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

void bench_hbao(const HbaoBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  const EstimatorInfo& gpu_info = find_estimator("hbao-split");
  const EstimatorInfo& cpu_info = find_estimator("hbao-split-cpu");
  const nlohmann::json overrides = parse_set_arguments(o.sets);
  const ParamSet gpu_params = resolve_params(gpu_info.name, gpu_info.params, overrides, "--set");
  nlohmann::json cpu_overrides = overrides;
  cpu_overrides.erase("gbuffer");
  const ParamSet cpu_params =
      resolve_params(cpu_info.name, cpu_info.params, cpu_overrides, "--set");
  const HbaoSettings s = hbao_settings_of(cpu_params);
  const bool raster = gpu_params.choice("gbuffer") == "raster";

  Scene scene = load_scene(o.scene);
  const View& view = scene.view(o.view);
  EmbreeScene embree(scene);
  const Camera camera = make_camera(view, w, h);
  const GBuffer g = render_gbuffer(embree, camera);

  std::string reason;
  vk::Context* vk = vk::shared_context(&reason);
  if (!vk) {
    std::printf("bench hbao: skipped: no Vulkan device (%s)\n", reason.c_str());
    return;
  }

  // hbao-split on the device; its first frame gives the G-buffer for the CPU twin.
  std::unique_ptr<HbaoDevice> device =
      raster ? std::make_unique<HbaoDevice>(*vk, s, scene, camera)
             : std::make_unique<HbaoDevice>(*vk, s, hbao_frame_from_gbuffer(g));
  const HbaoGpuResult first = device->run();

  // hbao-split-cpu on that G-buffer: the exact fetch count and the twin check.
  const HbaoFrame frame = device->frame();
  const HbaoCpuResult counted = hbao_split_cpu(frame, s, true);
  const double twin_diff = hbao_max_abs_difference(frame, counted.ao, first.ao);

  // The bare fetch loop: as many fetches per pixel, along walks of the same screen step.
  const double pixels = static_cast<double>(w) * h;
  const auto fetches = static_cast<double>(counted.depth_fetches);
  const int walks = s.directions * (1 + s.normal_rays);
  const int steps = std::max(1, static_cast<int>(std::lround(fetches / pixels / walks)));
  const double step_px = mean_step_pixels(frame, s);
  const double bare_fetches = pixels * walks * steps;
  BareFetch bare(*vk, device->depth_image(), walks, steps, static_cast<float>(step_px));

  // Timed on the device, alternating hbao-split and the bare loop repetition by repetition, so
  // that both see the same load (this machine is shared: the load drifts between runs, and a
  // ratio of two medians taken minutes apart carried it). Each repetition gives a ratio.
  for (int i = 0; i < o.warmup; ++i) {
    device->run();
    bare.run_ms();
  }
  std::vector<std::map<std::string, double>> gpu_runs;
  std::vector<double> gpu_totals, bare_runs, ratios;
  for (int i = 0; i < o.repetitions; ++i) {
    const HbaoGpuResult r = device->run();
    const double bare_ms_i = bare.run_ms();
    gpu_runs.push_back(r.pass_ms);
    gpu_totals.push_back(at(r.pass_ms, "total_ms"));
    bare_runs.push_back(bare_ms_i);
    const double tracing_i = at(r.pass_ms, "horizon_ms") + at(r.pass_ms, "normal_ms");
    ratios.push_back((fetches / tracing_i) / (bare_fetches / bare_ms_i));
  }
  const std::map<std::string, double> gpu = medians(gpu_runs);
  const double bare_ms = median(bare_runs);
  const double ratio = median(ratios);

  // hbao-split-cpu's times.
  for (int i = 0; i < o.warmup; ++i) hbao_split_cpu(frame, s);
  std::vector<std::map<std::string, double>> cpu_runs;
  std::vector<double> cpu_totals;
  for (int i = 0; i < o.repetitions; ++i) {
    const HbaoCpuResult r = hbao_split_cpu(frame, s);
    const double total = r.horizon_ms + r.normal_ms + r.blur_ms;
    cpu_runs.push_back(
        {{"horizon_ms", r.horizon_ms}, {"normal_ms", r.normal_ms}, {"blur_ms", r.blur_ms}});
    cpu_totals.push_back(total);
  }
  const std::map<std::string, double> cpu = medians(cpu_runs);
  const double cpu_total = median(cpu_totals);

  const double tracing_ms = at(gpu, "horizon_ms") + at(gpu, "normal_ms");
  const double hbao_rate = fetches / (tracing_ms * 1e-3);
  const double bare_rate = bare_fetches / (bare_ms * 1e-3);
  const double gpu_ao_ms = tracing_ms + at(gpu, "blur_ms");
  const double speedup = cpu_total / gpu_ao_ms;

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
      {"speedup_gpu_over_cpu", speedup},
      {"depth_fetches", counted.depth_fetches},
      {"hbao_fetches_per_s", hbao_rate},
      {"bare_walks", walks},
      {"bare_steps", steps},
      {"bare_step_px", step_px},
      {"bare_ms", bare_ms},
      {"bare_fetches_per_s", bare_rate},
      {"fetch_ratio", ratio},
      {"fetch_ratios", ratios},
      {"fetch_ratio_target", 0.5},
      {"twin_max_abs_difference", twin_diff},
  };
  if (raster)
    j["geometry_note"] = "gbuffer=raster: geometry_ms = raster pass + eye-space normals";
  else
    j["geometry_note"] = "gbuffer=embree: no geometry_ms (uploaded once, outside the frame)";

  std::ostringstream md;
  md << "# hbao-split bench: " << scene.name << "/" << view.name << " " << w << "x" << h << "\n\n"
     << "device: " << vk->device_description() << "; parameters: " << gpu_params.json().dump()
     << "\n\n| pass | GPU ms (median of " << o.repetitions
     << ") | CPU twin ms |\n|---|---:|---:|\n";
  for (const char* pass : {"geometry_ms", "horizon_ms", "normal_ms", "blur_ms"}) {
    const bool has_gpu = gpu.count(pass) > 0, has_cpu = cpu.count(pass) > 0;
    md << "| " << pass << " | " << (has_gpu ? fmt("%.3f", at(gpu, pass)) : "-") << " | "
       << (has_cpu ? fmt("%.3f", at(cpu, pass)) : "-") << " |\n";
  }
  md << "| total | " << fmt("%.3f", at(gpu, "total_ms")) << " | " << fmt("%.3f", cpu_total)
     << " |\n\n"
     << "- AO passes, CPU twin / GPU: " << fmt("%.2fx", speedup) << "\n"
     << "- depth fetches (horizon + normal passes): " << counted.depth_fetches << " ("
     << fmt("%.1f", fetches / pixels) << " per pixel)\n"
     << "- hbao-split: " << fmt("%.3f", hbao_rate * 1e-9) << " Gfetch/s; bare loop (" << walks
     << " walks x " << steps << " steps of " << fmt("%.2f", step_px)
     << " px): " << fmt("%.3f", bare_rate * 1e-9) << " Gfetch/s in " << fmt("%.3f", bare_ms)
     << " ms\n"
     << "- fetch ratio " << fmt("%.3f", ratio) << " (median of " << ratios.size()
     << " repetitions, each hbao-split's rate over the bare loop's timed right after it; "
     << fmt("%.3f", *std::min_element(ratios.begin(), ratios.end())) << " to "
     << fmt("%.3f", *std::max_element(ratios.begin(), ratios.end()))
     << "; target >= 0.5: " << (ratio >= 0.5 ? "met" : "NOT met") << ")\n"
     << "- twin max |CPU - GPU| over covered pixels: " << fmt("%.3g", twin_diff) << "\n"
     << "- " << j["geometry_note"].get<std::string>() << "\n";
  std::printf("%s", md.str().c_str());

  const RunContext context = make_run_context("bench hbao");
  ResultsFolder folder(o.out_dir, context);
  SqliteStore store(o.database);
  store.add_run(context);
  const ResultRow gpu_row = timing_row(context, gpu_info, gpu_params, overrides, scene, view, g,
                                       gpu_totals, gpu, vk->device_description());
  const ResultRow cpu_row = timing_row(context, cpu_info, cpu_params, cpu_overrides, scene, view, g,
                                       cpu_totals, cpu, context.device);
  for (const ResultRow& row : {gpu_row, cpu_row}) {
    folder.add(row);
    store.add(row);
  }
  write_text((fs::path(o.out_dir) / "bench_hbao.json").string(), j.dump(2) + "\n");
  write_text((fs::path(o.out_dir) / "bench_hbao.md").string(), md.str());
  std::printf("%s\n%s\n", (fs::path(o.out_dir) / "bench_hbao.json").string().c_str(),
              (fs::path(o.out_dir) / "bench_hbao.md").string().c_str());
}

}  // namespace aoeval
