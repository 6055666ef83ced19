#include "harness/bench/twin_bench.h"

#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>

#include "base/resolution.h"
#include "estimators/screen_space/frame_device.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "scenes/corpus.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace {

nlohmann::json without_gbuffer(nlohmann::json overrides) {
  overrides.erase("gbuffer");  // the CPU twins always read the Embree G-buffer
  return overrides;
}

Camera camera_of(const View& view, const std::string& res) {
  const auto [w, h] = parse_resolution(res);
  return make_camera(view, w, h);
}

}  // namespace

TwinBench::TwinBench(const TwinBenchOptions& o, const std::string& gpu_estimator,
                     const std::string& cpu_estimator)
    : options(o),
      gpu_info(find_estimator(gpu_estimator)),
      cpu_info(find_estimator(cpu_estimator)),
      gpu_overrides(parse_set_arguments(o.sets)),
      cpu_overrides(without_gbuffer(gpu_overrides)),
      gpu_params(resolve_params(gpu_info.name, gpu_info.params, gpu_overrides, "--set")),
      cpu_params(resolve_params(cpu_info.name, cpu_info.params, cpu_overrides, "--set")),
      raster(rasterises_frame(gpu_params)),
      scene(load_scene(o.scene)),
      view(scene.view(o.view)),
      embree(scene),
      camera(camera_of(view, o.res)),
      gbuffer(render_gbuffer(embree, camera)),
      vk(vk::shared_context(&skip_reason)) {}

const char* TwinBench::geometry_note() const {
  return raster ? "gbuffer=raster: geometry_ms = raster pass + eye-space normals"
                : "gbuffer=embree: no geometry_ms (uploaded once, outside the frame)";
}

nlohmann::json TwinBench::summary(const PassTimes& gpu, const PassTimes& cpu, double cpu_total_ms,
                                  double gpu_ao_ms) const {
  return {
      {"scene", scene.name},
      {"view", view.name},
      {"width", camera.width},
      {"height", camera.height},
      {"params", gpu_params.json()},
      {"device", vk->device_description()},
      {"cpu_threads",
       tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)},
      {"repetitions", options.repetitions},
      {"gpu_pass_ms", gpu},
      {"cpu_pass_ms", cpu},
      {"cpu_total_ms", cpu_total_ms},
      {"gpu_ao_ms", gpu_ao_ms},
      {"speedup_gpu_over_cpu", cpu_total_ms / gpu_ao_ms},
      {"geometry_note", geometry_note()},
  };
}

void TwinBench::write_pass_table(std::ostream& md, const std::string& title,
                                 std::initializer_list<const char*> passes, const PassTimes& gpu,
                                 const PassTimes& cpu, double cpu_total_ms) const {
  md << "# " << title << ": " << scene.name << "/" << view.name << " " << camera.width << "x"
     << camera.height << "\n\n"
     << "device: " << vk->device_description() << "; parameters: " << gpu_params.json().dump()
     << "\n\n| pass | GPU ms (median of " << options.repetitions
     << ") | CPU twin ms |\n|---|---:|---:|\n";
  for (const char* pass : passes) {
    const bool has_gpu = gpu.count(pass) > 0, has_cpu = cpu.count(pass) > 0;
    md << "| " << pass << " | " << (has_gpu ? format_number("%.3f", pass_ms(gpu, pass)) : "-")
       << " | " << (has_cpu ? format_number("%.3f", pass_ms(cpu, pass)) : "-") << " |\n";
  }
  md << "| total | " << format_number("%.3f", pass_ms(gpu, "total_ms")) << " | "
     << format_number("%.3f", cpu_total_ms) << " |\n\n";
}

void TwinBench::write(const std::string& command, const std::string& stem,
                      const nlohmann::json& summary, const std::string& markdown,
                      const std::vector<double>& gpu_totals_ms, const PassTimes& gpu,
                      const std::vector<double>& cpu_totals_ms, const PassTimes& cpu) const {
  namespace fs = std::filesystem;
  std::printf("%s", markdown.c_str());
  // Bench writes its rows once, at the end, and takes no lock on its folder.
  RunRecorder recorder(options.out_dir, options.database, command, FolderAccess::shared);
  recorder.register_run();
  const RunContext& context = recorder.context();
  const ResultRow gpu_row =
      timing_row(context, gpu_info, gpu_params, gpu_overrides, scene.name, view.name, camera.width,
                 camera.height, gpu_totals_ms, gpu, vk->device_description());
  const ResultRow cpu_row =
      timing_row(context, cpu_info, cpu_params, cpu_overrides, scene.name, view.name, camera.width,
                 camera.height, cpu_totals_ms, cpu, context.device);
  for (const ResultRow& row : {gpu_row, cpu_row}) recorder.record(row);
  const std::string json_path = (fs::path(options.out_dir) / (stem + ".json")).string();
  const std::string md_path = (fs::path(options.out_dir) / (stem + ".md")).string();
  write_text(json_path, summary.dump(2) + "\n");
  write_text(md_path, markdown);
  std::printf("%s\n%s\n", json_path.c_str(), md_path.c_str());
}

}  // namespace aoeval
