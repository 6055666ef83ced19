// `half-resolution` and `gtao-thickness` (ours, issue 32: the questions engine teams ask): see
// figures_engine.h for what each measures and figures_engine_checks.cpp for the checks.
#include <algorithm>

#include "drawing/error_maps.h"
#include "estimators/registry.h"
#include "harness/figures/figure_checks.h"
#include "harness/figures/figure_timing.h"
#include "harness/figures/figure_util.h"
#include "harness/figures/figures_engine.h"
#include "scenes/exr_io.h"

namespace aoeval::figures {

namespace {

AoDefinition definition_of(const std::string& estimator, const nlohmann::json& overrides) {
  const EstimatorInfo& info = find_estimator(estimator);
  return info.definition(resolve_params(info.name, info.params, overrides, "figure"));
}

// rmse_excess of `estimate` on the pixels of `mask` that `part` also marks; NaN when none.
double part_error(FigureContext& ctx, const std::string& scene, const std::string& view, int w,
                  int h, const AoDefinition& d, const std::vector<float>& estimate,
                  const std::vector<uint8_t>& mask, const std::vector<uint8_t>& part, bool inside) {
  std::vector<uint8_t> m(mask.size(), 0);
  size_t count = 0;
  for (size_t k = 0; k < m.size(); ++k) count += m[k] = mask[k] && (part[k] != 0) == inside;
  if (count == 0) return std::nan("");
  return score_against(ctx, scene, view, w, h, d, estimate, m).rmse_excess;
}

FigureResult half_resolution(FigureContext& ctx) {
  const std::vector<std::string> scenes =
      ctx.quick ? std::vector<std::string>{"bunny", "picket-fence"}
                : std::vector<std::string>{"bunny", "picket-fence", "chair", "wires"};
  const int long_side = ctx.pick(320, 64), warmup = ctx.quick ? 1 : 2, rounds = ctx.quick ? 6 : 15;
  FigureResult r;
  r.table.columns = {
      "estimator",     "scene",           "view",          "width",     "height",
      "edge_pixels",   "interior_pixels", "full_edge",     "half_edge", "full_interior",
      "half_interior", "edge_cost",       "interior_cost", "full_ms",   "half_ms"};
  HalfResNumbers numbers;
  std::vector<std::vector<OIIO::ImageBuf>> grid;
  for (const std::string estimator : {"gtao", "hbao-split"}) {
    if (!lookup_estimator(estimator)) {
      r.notes.push_back(estimator + ": not registered in this build, skipped");
      continue;
    }
    try {
      // The AO passes alone: the Embree G-buffer is uploaded once in prepare(), so no raster pass
      // enters either time; the downsample and upsample passes do enter the half-resolution one.
      const nlohmann::json full = {{"gbuffer", "embree"}, {"resolution", "full"}};
      const nlohmann::json half = {{"gbuffer", "embree"}, {"resolution", "half"}};
      const std::string& scene0 = scenes.front();
      const std::string view0 = ctx.session->scene(scene0).scene.views.front().name;
      const auto [w0, h0] = view_size(ctx, scene0, view0, long_side);
      const InterleavedTimes t = time_interleaved(
          ctx, {{estimator, full, scene0, view0, w0, h0}, {estimator, half, scene0, view0, w0, h0}},
          warmup, rounds);
      numbers.times.push_back({estimator, t.ms[0], t.ms[1]});
      for (const std::string& scene : scenes) {
        const std::string view = ctx.session->scene(scene).scene.views.front().name;
        const auto [w, h] = view_size(ctx, scene, view, long_side);
        const AoDefinition d = definition_of(estimator, full);
        const auto mask = compared_mask(ctx, scene, view, w, h, d);
        const auto edges = depth_edge_mask(
            ctx.session->gbuffer(scene, ctx.session->scene(scene).scene.view(view), w, h));
        const ScoredRun f = run_scored(ctx, estimator, full, scene, view, w, h);
        const ScoredRun s = run_scored(ctx, estimator, half, scene, view, w, h);
        HalfResScore score{estimator, scene};
        score.full_edge = part_error(ctx, scene, view, w, h, d, f.estimate, mask, edges, true);
        score.half_edge = part_error(ctx, scene, view, w, h, d, s.estimate, mask, edges, true);
        score.full_interior = part_error(ctx, scene, view, w, h, d, f.estimate, mask, edges, false);
        score.half_interior = part_error(ctx, scene, view, w, h, d, s.estimate, mask, edges, false);
        size_t n_edge = 0, n_interior = 0;
        for (size_t k = 0; k < mask.size(); ++k)
          if (mask[k]) (edges[k] ? n_edge : n_interior)++;
        const bool timed = scene == scene0;
        r.table.add({estimator, scene, view, std::to_string(w), std::to_string(h),
                     std::to_string(n_edge), std::to_string(n_interior), fmt(score.full_edge),
                     fmt(score.half_edge), fmt(score.full_interior), fmt(score.half_interior),
                     fmt(score.half_edge - score.full_edge),
                     fmt(score.half_interior - score.full_interior), timed ? fmt(t.median(0)) : "",
                     timed ? fmt(t.median(1)) : ""});
        numbers.scores.push_back(score);
        std::vector<float> edge_image(edges.size());  // edge pixels dark, interior white
        for (size_t k = 0; k < edges.size(); ++k) edge_image[k] = edges[k] ? 0.0f : 1.0f;
        grid.push_back({ao_image(w, h, f.estimate.data(), mask, scene + ": " + estimator + " full"),
                        ao_image(w, h, s.estimate.data(), mask, scene + ": " + estimator + " half"),
                        ao_image(w, h, edge_image.data(), mask, scene + ": edge pixels (dark)")});
      }
    } catch (const EstimatorUnavailable& e) {
      r.notes.push_back(estimator + ": skipped (" + e.what() + ")");
    }
  }
  write_image(ctx.path("half-resolution.png"),
              panel_grid(grid, "full vs half resolution (joint bilateral upsample)"));
  r.images = {"half-resolution.png"};
  r.checks = half_resolution_checks(numbers);
  r.measured =
      "gtao and hbao-split at their defaults with gbuffer=embree, resolution full and half, on " +
      std::to_string(scenes.size()) + " scenes (first view) at " + std::to_string(long_side) +
      " pixels on the long side, scored against the reference of their definition (" +
      std::to_string(ctx.session->reference_spec().spp) +
      " spp; rmse_excess, reference noise removed) on edge pixels (a pixel within " +
      std::to_string(kEdgeRadius) + " pixels that is uncovered or " +
      fmt(100.0 * kEdgeDepthJump, 2) +
      " % off in depth) and interior pixels; times: " + std::to_string(rounds) +
      " interleaved rounds on " + scenes.front() + " after " + std::to_string(warmup) +
      " warm-up (AO passes, plus downsample and upsample at half).";
  return r;
}

FigureResult gtao_thickness(FigureContext& ctx) {
  const EstimatorInfo& info = find_estimator("gtao-cpu");
  double declared = 0.0;
  for (const ParamSpec& p : info.params)
    if (p.name == "thickness") declared = p.default_value.get<double>();
  ThicknessNumbers n;
  n.declared_default = declared;
  n.thickness = ctx.quick
                    ? std::vector<double>{0.0, 0.5, 1.0}
                    : std::vector<double>{0.0, 0.025, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0};
  if (std::find(n.thickness.begin(), n.thickness.end(), declared) == n.thickness.end()) {
    n.thickness.push_back(declared);
    std::sort(n.thickness.begin(), n.thickness.end());
  }
  const std::vector<std::pair<std::string, bool>> scenes =
      ctx.quick
          ? std::vector<std::pair<std::string, bool>>{{"picket-fence", true}, {"bunny", false}}
          : std::vector<std::pair<std::string, bool>>{
                {"picket-fence", true}, {"chair", true},   {"wires", true},
                {"bunny", false},       {"dragon", false}, {"cornell-box", false}};
  const int long_side = ctx.pick(256, 48);
  FigureResult r;
  r.table.columns = {"scene", "view", "thin", "thickness", "rmse_excess", "true_rmse"};
  PlotSpec plot;
  plot.title = "gtao: rmse_excess against thickness";
  plot.x_label = "thickness (0 = off)";
  plot.y_label = "rmse_excess";
  for (const auto& [scene, thin] : scenes) {
    const std::string view = ctx.session->scene(scene).scene.views.front().name;
    const auto [w, h] = view_size(ctx, scene, view, long_side);
    PlotSeries series = make_series(scene + (thin ? " (thin)" : " (thick)"));
    std::vector<double> errors;
    for (double t : n.thickness) {
      const ScoredRun run = run_scored(ctx, "gtao-cpu", {{"thickness", t}}, scene, view, w, h);
      const double e = run.row.metrics.value("rmse_excess", std::nan(""));
      const double tr = run.row.true_metrics.value("rmse", std::nan(""));
      errors.push_back(e);
      series.x.push_back(t);
      series.y.push_back(e);
      r.table.add({scene, view, thin ? "yes" : "no", fmt(t), fmt(e), fmt(tr)});
    }
    n.scenes.push_back(scene);
    n.thin.push_back(thin);
    n.error.push_back(errors);
    plot.series.push_back(series);
  }
  render_plot(plot, ctx.path("gtao-thickness.png"));
  r.images = {"gtao-thickness.png"};
  r.checks = gtao_thickness_checks(n);
  r.measured =
      "gtao-cpu (the same bits as gtao) at its defaults but thickness, on thin scenes "
      "(picket-fence, chair, wires) and thick ones (bunny, dragon, cornell-box; --quick: "
      "picket-fence and bunny), first view, " +
      std::to_string(long_side) +
      " pixels on the long side, rmse_excess against the reference of its definition "
      "(cosine, dmax = R, falloff none) at " +
      std::to_string(ctx.session->reference_spec().spp) + " spp";
  return r;
}

}  // namespace

std::vector<Figure> engine_figures() {
  return {
      {"half-resolution", "ours (three.js and other engines' half-resolution AO)",
       "Half-resolution screen-space AO with a depth-aware (joint bilateral) upsample costs a "
       "quarter of the AO work and keeps interior pixels as accurate as full resolution; its "
       "error concentrates at depth discontinuities (the block artefacts engines report).",
       half_resolution},
      {"gtao-thickness", "ours (XeGTAO's hard-coded thickness, Filament's thin geometry)",
       "GTAO's thin-occluder heuristic (Jimenez et al. 2016, thickness) makes thin occluders "
       "(fences, legs, wires) more accurate, and one default serves thin and thick scenes alike.",
       gtao_thickness},
  };
}

}  // namespace aoeval::figures
