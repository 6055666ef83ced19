// What `aoeval bench gtao` and `aoeval bench hbao` share: each times a Vulkan screen-space
// estimator against its CPU twin (the same algorithm, TBB over rows) on the same G-buffer, and
// writes <stem>.json, <stem>.md and one results row per twin.
#pragma once

#include <initializer_list>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/default_paths.h"
#include "base/resolution.h"
#include "estimators/registry.h"
#include "estimators/vulkan/vk_context.h"
#include "harness/bench/bench_rows.h"
#include "scenes/camera.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval {

struct TwinBenchOptions {
  std::string scene = "bunny";
  std::string view;
  std::string res = kDefaultBenchResolution;
  std::vector<std::string> sets;  // KEY=VALUE for the GPU estimator (gbuffer applies to it only)
  int warmup = 1;
  int repetitions = 5;
  std::string out_dir;  // default: out/bench-<name>, set by the command
  std::string database = kDefaultDatabase;
};

// One twin bench's set-up: both estimators' parameters from one --set list, the scene, camera and
// Embree G-buffer, and the Vulkan device (null when there is none: `skip_reason` says why).
struct TwinBench {
  TwinBench(const TwinBenchOptions& options, const std::string& gpu_estimator,
            const std::string& cpu_estimator);

  const TwinBenchOptions& options;
  const EstimatorInfo& gpu_info;
  const EstimatorInfo& cpu_info;
  nlohmann::json gpu_overrides, cpu_overrides;
  ParamSet gpu_params, cpu_params;
  bool raster;  // gbuffer=raster: the GPU estimator rasterises its own G-buffer every frame
  Scene scene;
  const View& view;
  EmbreeScene embree;
  Camera camera;
  GBuffer gbuffer;
  vk::Context* vk = nullptr;
  std::string skip_reason;

  // What geometry_ms means for this G-buffer choice.
  const char* geometry_note() const;
  // The fields both benches' JSON carry: scene, size, parameters, device, threads, repetitions,
  // both twins' pass medians, and the AO time ratio (CPU twin over GPU).
  nlohmann::json summary(const PassTimes& gpu, const PassTimes& cpu, double cpu_total_ms,
                         double gpu_ao_ms) const;
  // "# <title>: scene/view WxH", the device and parameters, and the table of pass medians.
  void write_pass_table(std::ostream& md, const std::string& title,
                        std::initializer_list<const char*> passes, const PassTimes& gpu,
                        const PassTimes& cpu, double cpu_total_ms) const;
  // Writes one results row per twin (results folder and SQLite), <stem>.json and <stem>.md in
  // options.out_dir, and prints the files' paths.
  void write(const std::string& command, const std::string& stem, const nlohmann::json& summary,
             const std::string& markdown, const std::vector<double>& gpu_totals_ms,
             const PassTimes& gpu, const std::vector<double>& cpu_totals_ms,
             const PassTimes& cpu) const;
};

}  // namespace aoeval
