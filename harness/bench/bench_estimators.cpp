#include "harness/bench/bench_estimators.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "base/errors.h"
#include "base/resolution.h"
#include "base/summary.h"
#include "estimators/registry.h"
#include "harness/bench/bench_rows.h"
#include "harness/evaluation/evaluation.h"
#include "harness/evaluation/progress.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "scenes/corpus.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

struct BenchLine {
  std::string estimator, scene, backend;
  int width, height, repetitions;
  double median_ms, min_ms, max_ms, mpixel_per_s, precompute_ms;
};

std::string table(const std::vector<BenchLine>& lines, bool markdown) {
  std::ostringstream os;
  char buf[512];
  if (markdown) {
    os << "| estimator | backend | scene | resolution | median ms | min ms | max ms | Mpixel/s | "
          "precompute ms |\n"
       << "|---|---|---|---|---:|---:|---:|---:|---:|\n";
  } else {
    std::snprintf(buf, sizeof(buf), "%-18s %-7s %-14s %-10s %10s %10s %10s %10s %12s\n",
                  "estimator", "backend", "scene", "res", "median ms", "min ms", "max ms",
                  "Mpixel/s", "precomp ms");
    os << buf;
  }
  for (const auto& l : lines) {
    const std::string res = std::to_string(l.width) + "x" + std::to_string(l.height);
    std::snprintf(buf, sizeof(buf),
                  markdown ? "| %s | %s | %s | %s | %.3f | %.3f | %.3f | %.2f | %.1f |\n"
                           : "%-18s %-7s %-14s %-10s %10.3f %10.3f %10.3f %10.2f %12.1f\n",
                  l.estimator.c_str(), l.backend.c_str(), l.scene.c_str(), res.c_str(), l.median_ms,
                  l.min_ms, l.max_ms, l.mpixel_per_s, l.precompute_ms);
    os << buf;
  }
  return os.str();
}

std::string csv(const std::vector<BenchLine>& lines) {
  std::ostringstream os;
  os << "estimator,backend,scene,width,height,repetitions,time_ms_median,time_ms_min,time_ms_max,"
        "mpixel_per_s,precompute_ms\n";
  for (const auto& l : lines)
    os << l.estimator << ',' << l.backend << ',' << l.scene << ',' << l.width << ',' << l.height
       << ',' << l.repetitions << ',' << l.median_ms << ',' << l.min_ms << ',' << l.max_ms << ','
       << l.mpixel_per_s << ',' << l.precompute_ms << '\n';
  return os.str();
}

}  // namespace

void bench_estimators(const EstimatorBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  std::vector<const EstimatorInfo*> chosen;
  if (o.estimators.empty())
    for (const auto& e : estimator_registry()) chosen.push_back(&e);
  else
    for (const auto& name : o.estimators) chosen.push_back(&find_estimator(name));
  const nlohmann::json sets = parse_set_arguments(o.sets);
  for (auto it = sets.begin(); it != sets.end(); ++it) {
    bool used = false;
    for (const auto* e : chosen) used = used || e->find_param(it.key());
    if (!used) throw InputError("--set: no chosen estimator has a parameter '" + it.key() + "'");
  }
  // Every input is checked before the store is opened, so a bad scene or --set leaves no empty
  // database and no run without rows: each estimator's parameters, then each scene.
  std::vector<std::pair<nlohmann::json, ParamSet>> chosen_params;
  for (const EstimatorInfo* e : chosen) {
    nlohmann::json overrides = nlohmann::json::object();
    for (auto it = sets.begin(); it != sets.end(); ++it)
      if (e->find_param(it.key())) overrides[it.key()] = it.value();
    chosen_params.emplace_back(overrides, resolve_params(e->name, e->params, overrides, "--set"));
  }
  std::vector<Scene> scenes;
  for (const auto& scene_name : o.scenes) scenes.push_back(load_scene(scene_name));
  // Bench writes each timing row as it is measured, and takes no lock on its folder.
  RunRecorder recorder(o.out_dir, o.database, "bench estimators", FolderAccess::shared);
  recorder.register_run();
  const RunContext& context = recorder.context();
  std::vector<BenchLine> lines;
  Progress progress("bench", chosen.size() * o.scenes.size());
  for (Scene& scene : scenes) {
    const View& view = scene.view("");
    EmbreeScene es(scene);
    const Camera camera = make_camera(view, w, h);
    const GBuffer g = render_gbuffer(es, camera);
    const EstimateContext context_in{scene, es, g};
    for (size_t k = 0; k < chosen.size(); ++k) {
      const EstimatorInfo* e = chosen[k];
      const auto& [overrides, params] = chosen_params[k];
      auto estimator = e->create(params);
      double pre = 0.0;
      std::vector<double> times;
      std::map<std::string, std::vector<double>> passes;
      try {
        const auto t0 = std::chrono::steady_clock::now();
        estimator->prepare(context_in);
        pre = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count();
        for (int i = 0; i < o.warmup; ++i) estimator->run(context_in);
        for (int i = 0; i < o.repetitions; ++i) {
          const auto t = std::chrono::steady_clock::now();
          const EstimateResult r = estimator->run(context_in);
          const double wall =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t)
                  .count();
          const auto total = r.pass_ms.find("total_ms");
          times.push_back(total != r.pass_ms.end() ? total->second : wall);
          for (const auto& [pass, ms] : r.pass_ms)
            if (pass != "total_ms") passes[pass].push_back(ms);
        }
      } catch (const EstimatorUnavailable& unavailable) {
        // No backend here (e.g. no Vulkan device): say so and bench the others.
        std::fprintf(stderr, "bench: %s skipped: %s\n", e->name.c_str(), unavailable.what());
        progress.step(e->name + " " + scene.name);
        continue;
      }
      BenchLine l{e->name,
                  scene.name,
                  backend_name(e->backend),
                  g.width,
                  g.height,
                  o.repetitions,
                  median(times),
                  *std::min_element(times.begin(), times.end()),
                  *std::max_element(times.begin(), times.end()),
                  0.0,
                  pre};
      l.mpixel_per_s = static_cast<double>(g.pixel_count()) / (l.median_ms * 1e3);
      lines.push_back(l);
      PassTimes pass_times;
      for (const auto& [pass, values] : passes) pass_times[pass] = median(values);
      ResultRow row = timing_row(context, *e, params, overrides, scene.name, view.name, g.width,
                                 g.height, times, pass_times, backend_device(e->backend));
      row.precompute_ms = pre;
      recorder.record(row);  // a CPU estimator's row names the machine's CPU
      progress.step(e->name + " " + scene.name);
    }
  }
  std::printf("%s", table(lines, false).c_str());
  write_text((fs::path(o.out_dir) / "bench.csv").string(), csv(lines));
  write_text((fs::path(o.out_dir) / "bench.md").string(), table(lines, true));
  std::printf("%s\n%s\n", (fs::path(o.out_dir) / "bench.csv").string().c_str(),
              (fs::path(o.out_dir) / "bench.md").string().c_str());
}

}  // namespace aoeval
