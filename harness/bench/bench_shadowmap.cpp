#include "harness/bench/bench_shadowmap.h"

#include <algorithm>
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

struct Line {
  int lights = 0, map = 0;
  double total_ms = 0, shadow_ms = 0, accumulate_ms = 0;
};

}  // namespace

void bench_shadowmap(const ShadowmapBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  const EstimatorInfo& e = find_estimator("shadowmap-ao");
  nlohmann::json base = parse_set_arguments(o.sets);
  if (base.contains("lights") || base.contains("resolution"))
    throw InputError("--set: lights and resolution are set by --lights and --map-res");
  Scene scene = load_scene(o.scene);
  const View& view = scene.view("");
  EmbreeScene es(scene);
  const GBuffer g = render_gbuffer(es, make_camera(view, w, h));
  const EstimateContext in{scene, es, g};
  // Bench writes each timing row as it is measured, and takes no lock on its folder.
  RunRecorder recorder(o.out_dir, o.database, "bench shadowmap", FolderAccess::shared);
  recorder.register_run();
  const RunContext& context = recorder.context();
  std::vector<Line> lines;
  Progress progress("bench shadowmap", o.lights.size() * o.resolutions.size());
  for (int map : o.resolutions)
    for (int n : o.lights) {
      nlohmann::json overrides = base;
      overrides["lights"] = n;
      overrides["resolution"] = map;
      const ParamSet params = resolve_params(e.name, e.params, overrides, "bench shadowmap");
      auto est = e.create(params);
      std::vector<double> total, shadow, accumulate;
      try {
        est->prepare(in);
        for (int i = 0; i < o.warmup; ++i) est->run(in);
        for (int i = 0; i < o.repetitions; ++i) {
          const EstimateResult r = est->run(in);
          // mode=vertex bakes in prepare() and reports no passes per frame.
          if (!r.pass_ms.count("total_ms"))
            throw InputError("bench shadowmap: times mode=pixel only (the per-frame passes)");
          total.push_back(r.pass_ms.at("total_ms"));
          shadow.push_back(r.pass_ms.at("shadow_maps_ms"));
          accumulate.push_back(r.pass_ms.at("accumulate_ms"));
        }
      } catch (const EstimatorUnavailable& unavailable) {
        throw EstimatorUnavailable(std::string("bench shadowmap: ") + unavailable.what());
      }
      Line l{n, map, median(total), median(shadow), median(accumulate)};
      lines.push_back(l);
      const ResultRow row =
          timing_row(context, e, params, overrides, scene.name, view.name, g.width, g.height, total,
                     {{"shadow_maps_ms", l.shadow_ms}, {"accumulate_ms", l.accumulate_ms}},
                     backend_device(e.backend));
      recorder.record(row);
      progress.step(std::to_string(n) + " lights, " + std::to_string(map) + "²");
    }
  // Per light: a shadow map costs a render of the scene plus its texels; a light's accumulation
  // costs one shadow test per receiver (covered pixel).
  size_t covered = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) covered += g.covered(k) ? 1 : 0;
  std::ostringstream md, csv, console;
  md << "shadowmap-ao on " << scene.name << " (" << scene.triangle_count() << " triangles), "
     << g.width << "x" << g.height << " (" << covered << " covered pixels), device "
     << backend_device(e.backend) << ", median of " << o.repetitions << "\n\n"
     << "| lights | map | total ms | shadow maps ms | accumulate ms | ms per light (maps) | "
        "Mtexel/s (maps) | Mtests/s (accumulate) |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  csv << "lights,resolution,time_ms_median,shadow_maps_ms,accumulate_ms,ms_per_light,"
         "mtexel_per_s,mtests_per_s\n";
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%7s %6s %10s %12s %12s %10s %10s %10s\n", "lights", "map",
                "total ms", "maps ms", "accum ms", "ms/light", "Mtexel/s", "Mtests/s");
  console << buf;
  for (const Line& l : lines) {
    const double per_light = l.shadow_ms / l.lights;
    const double texels = static_cast<double>(l.lights) * l.map * l.map;
    const double mtexel = l.shadow_ms > 0 ? texels / (l.shadow_ms * 1e3) : 0.0;
    const double mtests = l.accumulate_ms > 0
                              ? static_cast<double>(covered) * l.lights / (l.accumulate_ms * 1e3)
                              : 0.0;
    std::snprintf(buf, sizeof(buf), "| %d | %d | %.1f | %.1f | %.1f | %.3f | %.1f | %.1f |\n",
                  l.lights, l.map, l.total_ms, l.shadow_ms, l.accumulate_ms, per_light, mtexel,
                  mtests);
    md << buf;
    csv << l.lights << ',' << l.map << ',' << l.total_ms << ',' << l.shadow_ms << ','
        << l.accumulate_ms << ',' << per_light << ',' << mtexel << ',' << mtests << '\n';
    std::snprintf(buf, sizeof(buf), "%7d %6d %10.1f %12.1f %12.1f %10.3f %10.1f %10.1f\n", l.lights,
                  l.map, l.total_ms, l.shadow_ms, l.accumulate_ms, per_light, mtexel, mtests);
    console << buf;
  }
  std::printf("%s", console.str().c_str());
  write_text((fs::path(o.out_dir) / "bench_shadowmap.csv").string(), csv.str());
  write_text((fs::path(o.out_dir) / "bench_shadowmap.md").string(), md.str());
  std::printf("%s\n", (fs::path(o.out_dir) / "bench_shadowmap.md").string().c_str());
}

}  // namespace aoeval
