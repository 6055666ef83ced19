#include "harness/bench/bench_scale.h"

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/errors.h"
#include "base/resolution.h"
#include "base/summary.h"
#include "base/text_files.h"
#include "drawing/plot.h"
#include "estimators/registry.h"
#include "harness/evaluation/progress.h"
#include "harness/scoring/metrics.h"
#include "references/cache_lock.h"
#include "references/reference.h"
#include "references/reference_cache.h"
#include "scenes/camera.h"
#include "scenes/corpus.h"
#include "scenes/instances.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Resident memory now (not the peak: the peak only grows over the N loop), after returning freed
// heap to the system so that the previous N's scene does not hide in it.
double rss_mib() {
  malloc_trim(0);
  long pages = 0, resident = 0;
  std::ifstream statm("/proc/self/statm");
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

// The base scene file with its instanced objects placed `n` times at the same density: the placer's
// square and ground planes grow as sqrt(n / base count) (ground planes never below 40 units; a
// terrain's resolution grows with its size, so its cells and relief stay as in the corpus).
std::string scaled_scene(const std::string& base, int n, const std::string& dir) {
  const fs::path src = fs::path(corpus_dir()) / (base + ".json");
  std::ifstream in(src);
  if (!in) throw InputError("bench scale: no corpus scene file " + src.string());
  nlohmann::json s = nlohmann::json::parse(in);
  double base_count = 0.0;
  for (const auto& o : s["objects"])
    if (o.contains("instances") && o["instances"].is_object())
      base_count = o["instances"].value("count", 0.0);
  if (!(base_count > 0.0))
    throw InputError("bench scale: scene '" + base + "' has no placer with a count");
  const double f = std::sqrt(n / base_count);
  for (auto& o : s["objects"]) {
    if (o.contains("instances") && o["instances"].is_object()) {
      o["instances"]["count"] = n;
      for (auto& v : o["instances"]["size"]) v = v.get<double>() * f;
    } else if (o.value("role", "") == "ground" && o.contains("params") &&
               o["params"].contains("size")) {
      auto& params = o["params"];
      const double was = params["size"][0].get<double>();
      for (auto& v : params["size"]) v = std::max(40.0, v.get<double>() * f);
      // A terrain keeps its cell size (and so its relief and triangle heights) as it grows.
      if (params.contains("resolution"))
        params["resolution"] = static_cast<int>(std::clamp(
            std::round(params["resolution"].get<double>() * params["size"][0].get<double>() / was),
            1.0, 2048.0));
    }
  }
  const fs::path out = fs::path(dir) / (base + "-n" + std::to_string(n) + ".json");
  write_text(out.string(), s.dump(1) + "\n");
  return out.string();
}

struct Build {
  double build_ms = 0, embree_mib = 0, rss_mib = 0, ref_ms = 0, mrays = 0;
};

struct EstimatorRow {
  std::string label, estimator;
  nlohmann::json set;
};

std::vector<EstimatorRow> estimator_rows(double cull, const std::vector<double>& far) {
  std::vector<EstimatorRow> rows;
  const char* trees[] = {"tree-sphere", "tree-ellipsoid", "tree-shells", "tree-volume"};
  // The cull rows (a radius only, far_field_angle 0: tree by tree) and the far-field rows.
  for (const char* e : trees)
    rows.push_back({e, e, {{"cull_occlusion", cull}, {"far_field_angle", 0.0}}});
  // The far field per pixel (far_field.h) and precomputed on the grid (far_grid.h, the default).
  for (const double a : far) {
    char label[64];
    for (const char* e : trees) {
      std::snprintf(label, sizeof label, "%s far %g", e, a);
      rows.push_back({label, e, {{"far_field_angle", a}, {"far_grid_cell", 0.0}}});
    }
    for (const char* e : trees) {
      std::snprintf(label, sizeof label, "%s far %g grid", e, a);
      rows.push_back({label, e, {{"far_field_angle", a}}});
    }
  }
  // tree-sphere at the exact cull (every tree that changes a bit) and at 1e-3, beside `cull`.
  rows.push_back({"tree-sphere exact", "tree-sphere", {{"far_field_angle", 0.0}}});
  if (cull != 1e-3)
    rows.push_back({"tree-sphere cull 1e-3",
                    "tree-sphere",
                    {{"cull_occlusion", 1e-3}, {"far_field_angle", 0.0}}});
  rows.push_back({"reeves-blau", "reeves-blau", nlohmann::json::object()});
  for (int rays : {1, 4})
    rows.push_back({"raytraced " + std::to_string(rays),
                    "raytraced",
                    {{"rays", rays}, {"weighting", "uniform"}}});
  return rows;
}

// The reference from the cache, or computed, timed and cached: {image, ms}; ms = 0 when served.
std::pair<ReferenceImage, double> cached_reference(const Scene& scene, const View& view,
                                                   const Camera& camera, const EmbreeScene& es,
                                                   const GBuffer& g,
                                                   const ReferenceSettings& settings, bool cache) {
  if (!cache) {
    const auto t0 = Clock::now();
    ReferenceImage ref = compute_reference(es, g, settings);
    return {std::move(ref), ms_since(t0)};
  }
  const std::string key = reference_cache_key(scene, camera, settings);
  const std::string path = reference_cache_path(key);
  if (auto hit = read_usable_cache_entry(path, key)) return {std::move(*hit), 0.0};
  const auto t0 = Clock::now();
  ReferenceImage ref = compute_reference(es, g, settings);
  const double ms = ms_since(t0);
  fill_cache_entry_once(
      path, [&] { return usable_cache_entry(path, key); },
      [&] {
        const OIIO::ImageBuf image = reference_to_image(ref, false);
        Attributes attributes = reference_attributes(scene, view, camera, settings);
        add_cache_attributes(attributes, key, image);
        write_exr(path, image, attributes);
      });
  return {std::move(ref), ms};
}

// Least-squares slope of log y against log x over the points where y > 0.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t k = 0; k < x.size() && k < y.size(); ++k) {
    if (!(y[k] > 0.0)) continue;
    const double a = std::log(x[k]), b = std::log(y[k]);
    sx += a, sy += b, sxx += a * a, sxy += a * b, ++n;
  }
  const double d = n * sxx - sx * sx;
  return n >= 2 && d > 0.0 ? (n * sxy - sx * sy) / d : NAN;
}

PlotSpec log_log(const std::string& title, const std::string& y_label) {
  PlotSpec p;
  p.title = title;
  p.x_label = "trees N";
  p.y_label = y_label;
  p.log_x = p.log_y = true;
  return p;
}

PlotSeries series(const std::string& label, const std::vector<double>& x,
                  const std::vector<double>& y) {
  PlotSeries s;
  s.label = label;
  s.x = x;
  s.y = y;
  return s;
}

}  // namespace

void bench_scale(const ScaleBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  const std::vector<EstimatorRow> rows = estimator_rows(o.cull, o.far);
  std::vector<ParamSet> params;
  for (const EstimatorRow& r : rows)
    params.push_back(
        resolve_params(r.estimator, find_estimator(r.estimator).params, r.set, "bench scale"));
  const fs::path scenes_dir = fs::path(o.out_dir) / "scenes";
  fs::create_directories(scenes_dir);
  ReferenceSettings settings;
  settings.spp = o.spp;
  settings.definition.weighting = Weighting::uniform;  // what the tree estimators estimate
  nlohmann::json out = nlohmann::json::array();
  Progress progress("bench scale", o.counts.size());
  for (const int n : o.counts) {
    nlohmann::json row = {{"n", n}};
    const double rss0 = rss_mib();
    Scene scene = load_scene_file(scaled_scene(o.base, n, scenes_dir.string()));
    row["instanced_triangles"] = instanced_triangle_count(scene);
    const View& view = scene.view("");
    const Camera camera = make_camera(view, w, h);
    {
      EmbreeScene es(scene);
      row["build_ms"] = es.build_ms();
      row["embree_mib"] = es.memory_bytes() / 1048576.0;
      row["rss_mib"] = rss_mib() - rss0;
      auto t0 = Clock::now();
      const GBuffer g = render_gbuffer(es, camera);
      row["gbuffer_ms"] = ms_since(t0);
      const auto [ref, ref_ms] =
          cached_reference(scene, view, camera, es, g, settings, o.cached_references);
      size_t covered = 0;
      std::vector<uint8_t> mask(g.pixel_count());
      for (size_t k = 0; k < g.pixel_count(); ++k) covered += mask[k] = g.covered(k);
      row["reference_ms"] = ref_ms;
      row["mrays_per_s"] = ref_ms > 0.0 ? static_cast<double>(covered) * o.spp / (ref_ms * 1e3)
                                        : NAN;  // served from the cache
      const EstimateContext context{scene, es, g};
      for (size_t k = 0; k < rows.size(); ++k) {
        auto e = find_estimator(rows[k].estimator).create(params[k]);
        t0 = Clock::now();
        e->prepare(context);
        const double prepare_ms = ms_since(t0);
        std::vector<double> times;
        EstimateResult r;
        for (int i = 0; i < o.repetitions; ++i) {
          t0 = Clock::now();
          r = e->run(context);
          times.push_back(ms_since(t0));
        }
        const Metrics m =
            compare_images({w, h, ref.ao.data()}, {w, h, r.ao.data()}, mask, ref.stderr_ao);
        row["estimators"][rows[k].label] = {{"ms", median(times)},
                                            {"prepare_ms", prepare_ms},
                                            {"rmse", m.rmse},
                                            {"rmse_excess", m.rmse_excess}};
      }
    }
    if (n <= o.copies_max) {
      try {
        const double rss1 = rss_mib();
        const Scene copies = scene_as_copies(scene);
        EmbreeScene es(copies);
        row["copies"] = {{"build_ms", es.build_ms()},
                         {"embree_mib", es.memory_bytes() / 1048576.0},
                         {"rss_mib", rss_mib() - rss1}};
        const GBuffer g = render_gbuffer(es, camera);
        const auto t0 = Clock::now();
        compute_reference(es, g, settings);
        size_t covered = 0;
        for (size_t k = 0; k < g.pixel_count(); ++k) covered += g.covered(k);
        row["copies"]["mrays_per_s"] = static_cast<double>(covered) * o.spp / (ms_since(t0) * 1e3);
      } catch (const InputError& refused) {
        row["copies"] = {{"refused", refused.what()}};
      }
    }
    out.push_back(row);
    progress.step(std::to_string(n) + " trees");
  }

  // The table, the slopes, the plot.
  std::vector<double> ns;
  auto column = [&](const auto& get) {
    std::vector<double> v;
    for (const auto& r : out) v.push_back(get(r));
    return v;
  };
  for (const auto& r : out) ns.push_back(r["n"].get<double>());
  std::ostringstream md;
  char buf[512];
  md << "# aoeval bench scale: " << o.base << " at N trees, " << w << "x" << h << ", reference "
     << o.spp << " spp (uniform), median of " << o.repetitions << "\n\n"
     << "| N | placed tris | build ms | Embree MiB | RSS MiB | G-buffer ms | ref Mrays/s | copies "
        "build ms | copies Embree MiB | copies Mrays/s |\n|---:|---:|---:|---:|---:|---:|---:|---:|"
        "---:|---:|\n";
  for (const auto& r : out) {
    const bool c = r.contains("copies") && r["copies"].contains("build_ms");
    std::snprintf(
        buf, sizeof buf, "| %d | %.3g | %.1f | %.1f | %.1f | %.1f | %.2f | %s | %s | %s |\n",
        r["n"].get<int>(), r["instanced_triangles"].get<double>(), r["build_ms"].get<double>(),
        r["embree_mib"].get<double>(), r["rss_mib"].get<double>(), r["gbuffer_ms"].get<double>(),
        r["mrays_per_s"].get<double>(),
        c ? std::to_string(r["copies"]["build_ms"].get<double>()).c_str() : "-",
        c ? std::to_string(r["copies"]["embree_mib"].get<double>()).c_str() : "-",
        c ? std::to_string(r["copies"]["mrays_per_s"].get<double>()).c_str() : "-");
    md << buf;
  }
  md << "\n| estimator |";
  for (double n : ns)
    md << " ms at " << n << " | rmse at " << n << " | prepare ms at " << n << " |";
  md << " ms slope |\n|---|";
  for (size_t k = 0; k < ns.size(); ++k) md << "---:|---:|---:|";
  md << "---:|\n";
  PlotSpec times = log_log("estimator ms", "ms");
  for (const EstimatorRow& e : rows) {
    const auto ms = column(
        [&](const nlohmann::json& r) { return r["estimators"][e.label]["ms"].get<double>(); });
    md << "| " << e.label << " |";
    for (const auto& r : out) {
      const nlohmann::json& row = r["estimators"][e.label];
      std::snprintf(buf, sizeof buf, " %.2f | %.4f | %.0f |", row["ms"].get<double>(),
                    row["rmse"].get<double>(), row.value("prepare_ms", 0.0));
      md << buf;
    }
    std::snprintf(buf, sizeof buf, " %.2f |\n", log_slope(ns, ms));
    md << buf;
    times.series.push_back(series(e.label, ns, ms));
  }
  nlohmann::json slopes;
  for (const char* key : {"build_ms", "embree_mib", "rss_mib", "gbuffer_ms", "mrays_per_s"})
    slopes[key] =
        log_slope(ns, column([&](const nlohmann::json& r) { return r[key].get<double>(); }));
  const double mr_ratio =
      out.back()["mrays_per_s"].get<double>() / out.front()["mrays_per_s"].get<double>();
  md << "\nlog-log slopes against N: ";
  for (auto it = slopes.begin(); it != slopes.end(); ++it) {
    std::snprintf(buf, sizeof buf, "%s %.3f; ", it.key().c_str(), it.value().get<double>());
    md << buf;
  }
  std::snprintf(buf, sizeof buf, "\nreference Mrays/s at N = %d over N = %d: %.3f\n",
                out.back()["n"].get<int>(), out.front()["n"].get<int>(), mr_ratio);
  md << buf;

  PlotSpec cost = log_log("scene cost", "ms / MiB / Mrays/s");
  for (const char* key : {"build_ms", "embree_mib", "rss_mib", "gbuffer_ms", "mrays_per_s"})
    cost.series.push_back(
        series(key, ns, column([&](const nlohmann::json& r) { return r[key].get<double>(); })));
  PlotSpec figure = log_log("aoeval bench scale", "");
  figure.width_in = 13.0;
  figure.height_in = 5.0;
  figure.panels = {cost, times};
  const fs::path dir(o.out_dir);
  write_text(
      (dir / "bench_scale.json").string(),
      nlohmann::json{{"rows", out}, {"slopes", slopes}, {"mrays_ratio", mr_ratio}}.dump(2) + "\n");
  write_text((dir / "bench_scale.md").string(), md.str());
  render_plot(figure, (dir / "bench_scale.png").string());
  std::printf("%s", md.str().c_str());
  std::printf("wrote %s\n", (dir / "bench_scale.md").string().c_str());
}

}  // namespace aoeval
