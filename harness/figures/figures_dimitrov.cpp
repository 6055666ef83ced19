// Dimitrov, Bavoil, Sainz 2008, "Horizon-Split Ambient Occlusion": Fig. 6 (radius R), Fig. 7
// (directions Nd), Fig. 11 (four presets at R = 0.3 against a ray tracer), Fig. 12 (horizon split
// against ray marching at equal rays) and Table 1 (geometry / HO / NO / blur ms by resolution,
// R = 0.2, Nd = 7, Nn = 1, Ns = 12). Accuracy is scored against the matched reference (cosine,
// dmax = R, linear falloff: §3.5) on the corpus's densest scanned mesh.
#include <algorithm>
#include <cmath>

#include "drawing/error_maps.h"
#include "estimators/registry.h"
#include "harness/figures/figure_checks.h"
#include "harness/figures/figure_timing.h"
#include "harness/figures/figure_util.h"
#include "scenes/corpus.h"
#include "scenes/exr_io.h"

namespace aoeval::figures {

namespace {

// hbao-split-cpu runs the same kernel source as the Vulkan hbao-split, deterministically and
// everywhere; the accuracy figures use it. Table 1 times the Vulkan passes when they exist.
const char* const kHbaoCpu = "hbao-split-cpu";

}  // namespace

// "Densest scanned mesh": the scanned-mesh scene of CONTRACT §6 with the most triangles.
std::string densest_scanned(FigureContext& ctx) {
  std::string best;
  size_t most = 0;
  for (const char* name : {"bunny", "dragon", "armadillo", "elephant"}) {
    const size_t n = ctx.session->scene(name).scene.triangle_count();
    if (n > most) most = n, best = name;
  }
  return best;
}

namespace {

std::string join(const std::vector<double>& v, int digits = 4) {
  std::string s;
  for (double x : v) s += std::string(s.empty() ? "" : ", ") + fmt(x, digits);
  return s;
}

struct Point {
  double rmse, true_rmse, mean_ao;
  std::vector<float> estimate;
  nlohmann::json params;  // the row's effective parameters
};

// A parameter of a row as its tables print it: the value that ran, not a literal beside it.
std::string param_text(const nlohmann::json& params, const std::string& key) {
  return format_param_value(params.at(key));
}

Point score_point(FigureContext& ctx, const std::string& estimator, const nlohmann::json& o,
                  const std::string& scene, int w, int h) {
  const ScoredRun run = run_scored(ctx, estimator, o, scene, "main", w, h);
  const auto mask = compared_mask(ctx, scene, "main", w, h, true_ao_definition());
  return {run.row.metrics["rmse"].get<double>(), run.row.true_metrics["rmse"].get<double>(),
          masked_mean(run.estimate, mask), run.estimate, run.row.params};
}

// ---- Fig. 6: R --------------------------------------------------------------------------------

FigureResult fig6(FigureContext& ctx) {
  const std::string scene = densest_scanned(ctx);
  const auto [w, h] = view_size(ctx, scene, "main", ctx.pick(240, 48));
  const std::vector<double> radii = {0.05, 0.1, 0.2, 0.3, 0.5};
  FigureResult r;
  r.table.columns = {"R",     "Nd",     "Ns",           "Nn",        "scene",
                     "width", "height", "rmse_matched", "rmse_true", "mean_ao"};
  std::vector<double> rmse, mean;
  std::vector<OIIO::ImageBuf> panels;
  const auto mask = compared_mask(ctx, scene, "main", w, h, true_ao_definition());
  PlotSpec plot;
  plot.title = "Dimitrov et al. 2008 Fig. 6: radius of influence R";
  plot.x_label = "R (scene units)";
  plot.y_label = "RMSE vs matched reference; mean AO";
  plot.log_x = true;
  PlotSeries e = make_series("RMSE (matched)"), m = make_series("mean AO");
  for (double R : radii) {
    const Point p = score_point(ctx, kHbaoCpu, {{"R", R}}, scene, w, h);
    rmse.push_back(p.rmse);
    mean.push_back(p.mean_ao);
    r.table.add({fmt(R), param_text(p.params, "Nd"), param_text(p.params, "Ns"),
                 param_text(p.params, "Nn"), scene, std::to_string(w), std::to_string(h),
                 fmt(p.rmse), fmt(p.true_rmse), fmt(p.mean_ao)});
    if (R == 0.1 || R == 0.2 || R == 0.5)  // the paper's three panels
      panels.push_back(ao_image(w, h, p.estimate.data(), mask, "R = " + fmt(R)));
    e.x.push_back(R), e.y.push_back(p.rmse), m.x.push_back(R), m.y.push_back(p.mean_ao);
  }
  plot.series = {e, m};
  write_image(ctx.path("dimitrov-fig6.png"),
              panel_grid({panels}, "Dimitrov et al. 2008 Fig. 6: effect of R (" + scene + ")"));
  render_plot(plot, ctx.path("dimitrov-fig6-plot.png"));
  r.images = {"dimitrov-fig6.png", "dimitrov-fig6-plot.png"};
  r.checks = dimitrov_fig6_checks({mean, rmse});
  r.measured = std::string(kHbaoCpu) + " (Nd 8, Ns 18, Nn 1, attenuation, jitter, blur) on " +
               scene + "/main at " + std::to_string(w) + "x" + std::to_string(h) +
               "; each R scored against its own matched reference (cosine, dmax = R, linear) at " +
               std::to_string(ctx.session->reference_spec().spp) + " spp.";
  return r;
}

// ---- Fig. 7: Nd -------------------------------------------------------------------------------

FigureResult fig7(FigureContext& ctx) {
  const std::string scene = densest_scanned(ctx);
  const auto [w, h] = view_size(ctx, scene, "main", ctx.pick(240, 48));
  const std::vector<int> nds = {1, 2, 4, 7, 10, 16};
  // Interleaved rounds of Nd 1 and Nd 16 decide the timing check by the rank test
  // (figure_timing.h); 11 once gave p = 0.003 under load.
  const int reps = ctx.pick(21, 5);
  FigureResult r;
  r.table.columns = {"Nd",           "R",         "scene",   "width",         "height",
                     "rmse_matched", "rmse_true", "mean_ao", "time_ms_median"};
  std::vector<double> rmse;
  std::vector<Contender> contenders;
  for (int nd : nds)
    contenders.push_back({kHbaoCpu, {{"R", 0.2}, {"Nd", nd}}, scene, "main", w, h});
  const InterleavedTimes t = time_interleaved(ctx, contenders, 1, reps);
  std::vector<OIIO::ImageBuf> panels;
  const auto mask = compared_mask(ctx, scene, "main", w, h, true_ao_definition());
  PlotSpec plot;
  plot.title = "Dimitrov et al. 2008 Fig. 7: number of directions Nd (R = 0.2)";
  plot.x_label = "Nd";
  plot.y_label = "RMSE vs matched reference";
  plot.log_x = true;
  PlotSeries e = make_series("RMSE (matched)");
  for (size_t i = 0; i < nds.size(); ++i) {
    const int nd = nds[i];
    const Point p = score_point(ctx, kHbaoCpu, contenders[i].overrides, scene, w, h);
    rmse.push_back(p.rmse);
    r.table.add({std::to_string(nd), "0.2", scene, std::to_string(w), std::to_string(h),
                 fmt(p.rmse), fmt(p.true_rmse), fmt(p.mean_ao), fmt(t.median(i))});
    if (nd == 1 || nd == 4 || nd == 10)  // the paper's three panels
      panels.push_back(ao_image(w, h, p.estimate.data(), mask, "Nd = " + std::to_string(nd)));
    e.x.push_back(nd), e.y.push_back(p.rmse);
  }
  plot.series = {e};
  write_image(ctx.path("dimitrov-fig7.png"),
              panel_grid({panels}, "Dimitrov et al. 2008 Fig. 7: effect of Nd (" + scene + ")"));
  render_plot(plot, ctx.path("dimitrov-fig7-plot.png"));
  r.images = {"dimitrov-fig7.png", "dimitrov-fig7-plot.png"};
  r.checks = dimitrov_fig7_checks({rmse[0], rmse[2], rmse[4], t.ms.front(), t.ms.back()});
  r.measured = std::string(kHbaoCpu) + " (R 0.2, Ns 18, Nn 1, blur) on " + scene + "/main at " +
               std::to_string(w) + "x" + std::to_string(h) +
               ", against the matched reference (cosine, dmax 0.2, linear); time = median of " +
               std::to_string(reps) +
               " interleaved rounds (every Nd once per round, rotating order), the timing check "
               "decided by the one-sided Mann-Whitney rank test at alpha 0.01.";
  return r;
}

// ---- Fig. 11: presets -------------------------------------------------------------------------

FigureResult fig11(FigureContext& ctx) {
  const std::string scene = densest_scanned(ctx);
  const auto [w, h] = view_size(ctx, scene, "main", ctx.pick(240, 48));
  struct Preset {
    std::string label;
    int nd, ns, nn;
  };
  // Fig. 11 caption: R = 0.3 with linear attenuation.
  const std::vector<Preset> presets = {{"(a) Nd 6 Ns 9 Nn 0", 6, 9, 0},
                                       {"(b) Nd 8 Ns 18 Nn 0", 8, 18, 0},
                                       {"(c) Nd 8 Ns 18 Nn 1", 8, 18, 1},
                                       {"(d) Nd 18 Ns 25 Nn 2", 18, 25, 2}};
  // Interleaved rounds (figure_timing.h); 11 once left the b -> c step at p = 0.008.
  const int reps = ctx.pick(21, 5);
  FigureResult r;
  r.table.columns = {"preset",        "Nd",     "Ns",           "Nn",           "R",
                     "width",         "height", "rmse_matched", "ssim_matched", "rmse_true",
                     "time_ms_median"};
  std::vector<double> rmse;
  std::vector<std::vector<float>> estimates;
  std::vector<OIIO::ImageBuf> top, bottom;
  AoDefinition definition;
  std::vector<Contender> contenders;
  for (const auto& p : presets)
    contenders.push_back(
        {kHbaoCpu, {{"R", 0.3}, {"Nd", p.nd}, {"Ns", p.ns}, {"Nn", p.nn}}, scene, "main", w, h});
  const InterleavedTimes t = time_interleaved(ctx, contenders, 1, reps);
  for (size_t i = 0; i < presets.size(); ++i) {
    const auto& p = presets[i];
    const ScoredRun run = run_scored(ctx, kHbaoCpu, contenders[i].overrides, scene, "main", w, h);
    definition = find_estimator(kHbaoCpu).definition(ParamSet(run.row.params));
    rmse.push_back(run.row.metrics["rmse"].get<double>());
    r.table.add({p.label.substr(0, 3), std::to_string(p.nd), std::to_string(p.ns),
                 std::to_string(p.nn), param_text(run.row.params, "R"), std::to_string(w),
                 std::to_string(h), fmt(rmse.back()), fmt(run.row.metrics["ssim"].get<double>()),
                 fmt(run.row.true_metrics["rmse"].get<double>()), fmt(t.median(i))});
    estimates.push_back(run.estimate);
  }
  const ReferenceImage& ref = reference_of(ctx, scene, "main", w, h, definition);
  const auto mask = compared_mask(ctx, scene, "main", w, h, definition);
  for (size_t i = 0; i < presets.size(); ++i) {
    top.push_back(ao_image(w, h, estimates[i].data(), mask, presets[i].label));
    bottom.push_back(abs_error_map(w, h, ref.ao.data(), estimates[i].data(), mask, 0.2f));
  }
  top.push_back(
      ao_image(w, h, ref.ao.data(), mask,
               "(e) ray traced, " + std::to_string(ctx.session->reference_spec().spp) + " spp"));
  write_image(ctx.path("dimitrov-fig11.png"),
              panel_grid({top, bottom}, "Dimitrov et al. 2008 Fig. 11: presets at R = 0.3"));
  r.images = {"dimitrov-fig11.png"};
  r.checks = dimitrov_fig11_checks({rmse, t.ms});
  r.measured = std::string(kHbaoCpu) +
               " with the four presets of the Fig. 11 caption (R 0.3, "
               "linear attenuation, blur) on " +
               scene + "/main at " + std::to_string(w) + "x" + std::to_string(h) +
               "; (e) is the matched Embree reference (cosine, dmax 0.3, "
               "linear) instead of Mental Ray; error maps share the scale [0, 0.2]; times from " +
               std::to_string(reps) +
               " interleaved rounds, the cost check decided by the one-sided Mann-Whitney rank "
               "test at alpha 0.01.";
  return r;
}

// ---- Fig. 12: horizon split vs ray marching at equal rays -------------------------------------

FigureResult fig12(FigureContext& ctx) {
  const std::string scene = densest_scanned(ctx);
  const auto [w, h] = view_size(ctx, scene, "main", ctx.pick(240, 48));
  const std::vector<int> budgets =
      ctx.quick ? std::vector<int>{4, 16} : std::vector<int>{4, 8, 16, 32, 64};
  FigureResult r;
  r.table.columns = {"rays_per_pixel", "estimator", "Nd",     "Nn", "rays", "R", "Ns",
                     "rmse_matched",   "rmse_true", "time_ms"};
  PlotSpec plot;
  plot.title = "Dimitrov et al. 2008 Fig. 12: error at equal rays per pixel";
  plot.x_label = "rays per pixel (horizon split: Nd (1 + Nn))";
  plot.y_label = "RMSE vs matched reference";
  plot.log_x = plot.log_y = true;
  PlotSeries hs = make_series("horizon split (hbao-split-cpu, Nn 1)"),
             rm = make_series("ray marching (raymarch-ssao)");
  std::vector<double> e_hs, e_rm;
  std::vector<OIIO::ImageBuf> panels;
  const auto mask = compared_mask(ctx, scene, "main", w, h, true_ao_definition());
  for (int b : budgets) {
    // Horizon split traces Nd horizon rays and Nd * Nn normal rays (§3); blur off for both so the
    // comparison is of the estimators, not of the post-filter.
    const nlohmann::json oh = {{"R", 0.3}, {"Nd", b / 2}, {"Nn", 1}, {"blur", false}};
    const nlohmann::json orm = {{"R", 0.3}, {"rays", b}};
    const ScoredRun a = run_scored(ctx, kHbaoCpu, oh, scene, "main", w, h);
    const ScoredRun c = run_scored(ctx, "raymarch-ssao", orm, scene, "main", w, h);
    e_hs.push_back(a.row.metrics["rmse"].get<double>());
    e_rm.push_back(c.row.metrics["rmse"].get<double>());
    r.table.add({std::to_string(b), kHbaoCpu, std::to_string(b / 2), param_text(a.row.params, "Nn"),
                 "", param_text(a.row.params, "R"), param_text(a.row.params, "Ns"),
                 fmt(e_hs.back()), fmt(a.row.true_metrics["rmse"].get<double>()),
                 fmt(a.row.time_ms_median)});
    r.table.add({std::to_string(b), "raymarch-ssao", "", "", std::to_string(b),
                 param_text(c.row.params, "R"), param_text(c.row.params, "Ns"), fmt(e_rm.back()),
                 fmt(c.row.true_metrics["rmse"].get<double>()), fmt(c.row.time_ms_median)});
    hs.x.push_back(b), hs.y.push_back(e_hs.back()), rm.x.push_back(b), rm.y.push_back(e_rm.back());
    if (b == 8 || (ctx.quick && b == 4)) {
      panels.push_back(
          ao_image(w, h, a.estimate.data(), mask, "horizon split, " + std::to_string(b) + " rays"));
      panels.push_back(
          ao_image(w, h, c.estimate.data(), mask, "ray marching, " + std::to_string(b) + " rays"));
    }
  }
  plot.series = {hs, rm};
  write_image(ctx.path("dimitrov-fig12.png"),
              panel_grid({panels}, "Dimitrov et al. 2008 Fig. 12: equal rays per pixel"));
  render_plot(plot, ctx.path("dimitrov-fig12-plot.png"));
  r.images = {"dimitrov-fig12.png", "dimitrov-fig12-plot.png"};
  r.checks = dimitrov_fig12_checks({budgets, e_hs, e_rm});
  r.measured =
      "equal rays per pixel b: hbao-split-cpu with Nd = b/2, Nn = 1 (b rays: Nd horizon "
      "+ Nd Nn normal) and raymarch-ssao with b rays, both R 0.3, Ns 18, linear "
      "attenuation, no blur, on " +
      scene + "/main at " + std::to_string(w) + "x" + std::to_string(h) +
      ", against the shared matched reference (cosine, dmax 0.3, "
      "linear).";
  return r;
}

}  // namespace

std::vector<Check> dimitrov_fig6_checks(const DimitrovFig6Numbers& n) {
  if (n.mean.size() < 2 || n.rmse.size() < 2)
    return {{"mean AO and RMSE at two radii or more", false, "not run"}};
  bool stronger = true;
  for (size_t i = 1; i < n.mean.size(); ++i) stronger = stronger && n.mean[i] < n.mean[i - 1];
  return {{"mean AO falls strictly as R grows ('stronger ambient occlusion values due to the "
           "existence of more occluders')",
           stronger, "mean AO " + join(n.mean)},
          {"matched RMSE at the largest R > at the smallest, at fixed Nd, Ns, Nn ('occluder "
           "undersampling ... requiring more sampling rays')",
           n.rmse.back() > n.rmse.front(), "RMSE " + join(n.rmse)}};
}

std::vector<Check> dimitrov_fig7_checks(const DimitrovFig7Numbers& n) {
  // Time proportional to Nd: Nd 16 is slower than 4 x Nd 1 (claimed, so it must be significant).
  const double p = p_slower(n.ms_nd16, n.ms_nd1, 4.0);
  return {{"matched RMSE falls across the paper's panels: RMSE(Nd 1) > RMSE(Nd 4) > RMSE(Nd 10)",
           n.rmse_nd1 > n.rmse_nd4 && n.rmse_nd4 > n.rmse_nd10,
           fmt(n.rmse_nd1, 4) + " > " + fmt(n.rmse_nd4, 4) + " > " + fmt(n.rmse_nd10, 4)},
          {"time grows with Nd ('the total number of traced rays is proportional to this "
           "parameter'): t(Nd 16) slower than 4 x t(Nd 1) by the rank test at p < 0.01",
           p < kTimingAlpha,
           "t(Nd 16) / t(Nd 1) = " + fmt(median(n.ms_nd16) / median(n.ms_nd1), 3) + " (median ms " +
               fmt(median(n.ms_nd1), 4) + ", " + fmt(median(n.ms_nd16), 4) + "); " + p_text(p)}};
}

std::vector<Check> dimitrov_fig11_checks(const DimitrovFig11Numbers& n) {
  if (n.rmse.size() != 4 || n.ms.size() != 4)
    return {{"the four presets scored and timed", false, "not run"}};
  double worst = 0.0;  // the largest p of the three steps: each must be significant
  std::string ps, medians;
  for (size_t i = 0; i < 4; ++i) {
    medians += std::string(i ? ", " : "") + fmt(median(n.ms[i]), 4);
    if (i == 0) continue;
    const double p = p_slower(n.ms[i], n.ms[i - 1]);
    worst = std::max(worst, p);
    ps += std::string(i > 1 ? ", " : "") + fmt(p, 2);
  }
  return {{"the quality preset (d) is closer to the ray tracer than the performance preset (a): "
           "RMSE(d) < RMSE(a)",
           n.rmse[3] < n.rmse[0], fmt(n.rmse[3], 4) + " vs " + fmt(n.rmse[0], 4)},
          {"adding normal occlusion improves proximity occlusion: RMSE(c) < RMSE(b)",
           n.rmse[2] < n.rmse[1], fmt(n.rmse[2], 4) + " vs " + fmt(n.rmse[1], 4)},
          {"cost rises from performance to quality: t(a) < t(b) < t(c) < t(d), each step slower "
           "by the rank test at p < 0.01",
           worst < kTimingAlpha, "median ms " + medians + "; per step p = " + ps}};
}

std::vector<Check> dimitrov_fig12_checks(const DimitrovFig12Numbers& n) {
  const size_t k = n.budgets.size();
  if (k == 0 || n.horizon_split.size() != k || n.ray_marching.size() != k)
    return {{"both estimators at every ray count", false, "not run"}};
  size_t wins = 0;
  for (size_t i = 0; i < k; ++i) wins += n.horizon_split[i] < n.ray_marching[i] ? 1 : 0;
  return {{"at the fewest rays (" + std::to_string(n.budgets.front()) +
               " per pixel) horizon split has the lower matched RMSE",
           n.horizon_split.front() < n.ray_marching.front(),
           fmt(n.horizon_split.front(), 4) + " vs " + fmt(n.ray_marching.front(), 4)},
          {"horizon split has the lower matched RMSE at every ray count ('ray marching requires "
           "more rays than horizon occlusion')",
           wins == k,
           std::to_string(wins) + " of " + std::to_string(k) + "; horizon split " +
               join(n.horizon_split) + "; ray marching " + join(n.ray_marching)}};
}

FigureResult dimitrov_table1(FigureContext& ctx);  // figures_dimitrov_table1.cpp

std::vector<Figure> dimitrov_figures() {
  return {
      {"dimitrov-fig6", "Dimitrov et al. 2008, Fig. 6 and §3.6",
       "Increasing the radius of influence R gives stronger ambient occlusion (more occluders) "
       "and undersamples occluders in the hemisphere, requiring more rays for the same quality "
       "(panels R = 0.1, 0.2, 0.5).",
       fig6},
      {"dimitrov-fig7", "Dimitrov et al. 2008, Fig. 7 and §3.6",
       "More initial directions Nd (panels Nd = 1, 4, 10 at R = 0.2) give a smoother, more "
       "accurate result; the number of traced rays is proportional to Nd.",
       fig7},
      {"dimitrov-fig11", "Dimitrov et al. 2008, Fig. 11",
       "Presets at R = 0.3 with linear attenuation go from performance (a: Nd 6, Ns 9, Nn 0) to "
       "quality (d: Nd 18, Ns 25, Nn 2, 5 fps), adding normal occlusion (b -> c) improves "
       "proximity occlusion, and the result is similar to a ray tracer (e: 256 rays, 8 min).",
       fig11},
      {"dimitrov-fig12", "Dimitrov et al. 2008, Fig. 12 and §5",
       "Horizon occlusion converges faster than Monte-Carlo ray marching: ray marching requires "
       "more rays than horizon-split occlusion to produce similar images.",
       fig12},
      {"dimitrov-table1", "Dimitrov et al. 2008, Table 1",
       "For R = 0.2, Nd = 7, Nn = 1, Ns = 12 on a 750k-triangle model, geometry / HO / NO / blur "
       "take 4.02 / 7.16 / 4.67 / 0.71 ms at 640x480 up to 6.68 / 39.66 / 37.41 / 4.35 ms at "
       "1600x1153 (GeForce 8800 GTX): horizon occlusion costs about as much as one normal ray, "
       "blur is the cheapest pass, and HO and NO grow with the pixel count.",
       dimitrov_table1},
  };
}

}  // namespace aoeval::figures
