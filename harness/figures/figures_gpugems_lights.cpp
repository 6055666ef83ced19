// Pharr and Green 2004, GPU Gems ch. 17 §17.3: "The distribution of the lights on the sphere also
// affects the final quality. The most obvious method is to use polar coordinates, with lights
// distributed at evenly spaced longitudes and latitudes, but this tends to concentrate too many
// samples at the poles. Instead, you should use a uniform distribution on the sphere." Measured
// with shadowmap-ao: error against the number of lights for both placements, on a model on a
// ground plane (the chapter's setting), and the placements' share of lights near the poles.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "drawing/plot.h"
#include "estimators/shadowmap_ao/shadowmap_ao.h"
#include "harness/figures/figure_util.h"
#include "harness/figures/figures_gpugems.h"

namespace aoeval::figures {

namespace {

// The share of lights within 30° of either pole (±Y); 1 - cos 30° = 0.134 for a uniform set.
double polar_share(const std::vector<glm::vec3>& d) {
  const double c = std::cos(std::numbers::pi / 6);
  double n = 0;
  for (const auto& v : d) n += std::abs(v.y) > c ? 1 : 0;
  return d.empty() ? 0.0 : n / static_cast<double>(d.size());
}

}  // namespace

std::vector<Check> lights_checks(const LightsNumbers& n) {
  std::vector<Check> checks;
  const size_t k = n.lights.size();
  const bool have = k >= 2 && n.uniform_rmse.size() == k && n.latlong_rmse.size() == k;
  const double uniform_share = 1.0 - std::cos(std::numbers::pi / 6);
  checks.push_back(
      {"lat-long concentrates lights at the poles: within 30° of ±Y it puts at least 1.5x the "
       "uniform set's share (a uniform set's is 1 - cos 30° = 0.134)",
       n.latlong_polar >= 1.5 * n.uniform_polar,
       "lat-long " + fmt(n.latlong_polar, 3) + ", uniform " + fmt(n.uniform_polar, 3) +
           " (expected " + fmt(uniform_share, 3) + ")"});
  if (!have) return checks;
  checks.push_back(
      {"the uniform set's error falls as lights are added: RMSE at the most lights <= "
       "0.75x RMSE at the fewest",
       n.uniform_rmse.back() <= 0.75 * n.uniform_rmse.front(),
       fmt(n.uniform_rmse.front(), 3) + " at " + std::to_string(n.lights.front()) + " -> " +
           fmt(n.uniform_rmse.back(), 3) + " at " + std::to_string(n.lights.back())});
  // The chapter's range of "good results" is 128 to 1024 lights; at --quick scale (fewer lights)
  // the comparison covers the counts there are.
  const int from = std::min(128, n.lights.back());
  bool all = true;
  std::string measured;
  for (size_t i = 0; i < k; ++i) {
    if (n.lights[i] < from) continue;
    all = all && n.uniform_rmse[i] < n.latlong_rmse[i];
    measured += (measured.empty() ? "" : "; ") + std::to_string(n.lights[i]) + ": " +
                fmt(n.uniform_rmse[i], 3) + " vs " + fmt(n.latlong_rmse[i], 3);
  }
  checks.push_back({"uniform beats lat-long at every light count from " + std::to_string(from) +
                        " on (RMSE uniform vs lat-long)",
                    all, measured});
  checks.push_back(
      {"lat-long's excess is a bias that more lights do not remove: at the most lights its RMSE "
       ">= 1.5x the uniform set's",
       n.latlong_rmse.back() >= 1.5 * n.uniform_rmse.back(),
       fmt(n.latlong_rmse.back(), 3) + " vs " + fmt(n.uniform_rmse.back(), 3)});
  return checks;
}

FigureResult gpugems_lights(FigureContext& ctx) {
  const std::string scene = "elephant", view = "main";
  const AoDefinition accessibility{Weighting::uniform};
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(160, 40));
  const std::vector<int> counts =
      ctx.quick ? std::vector<int>{16, 64} : std::vector<int>{32, 64, 128, 256, 512, 1024};
  const int map = ctx.pick(256, 64);
  const View& v = ctx.session->scene(scene).scene.view(view);
  const GBuffer& g = ctx.session->gbuffer(scene, v, w, h);
  const auto all = compared_mask(ctx, scene, view, w, h, accessibility);
  FigureResult r;
  r.table.columns = {"distribution", "lights", "resolution",  "width", "height",
                     "polar_share",  "rmse",   "rmse_excess", "bias",  "frame_ms"};
  PlotSpec plot;
  plot.title = "GPU Gems ch. 17 §17.3: shadow-mapped lights, uniform vs. lat-long";
  plot.x_label = "lights on the sphere";
  plot.y_label = "RMSE vs uniform-weighted reference";
  plot.log_x = plot.log_y = true;
  LightsNumbers numbers;
  numbers.lights = counts;
  for (const char* dist : {"uniform", "latlong"}) {
    const LightDistribution d =
        std::string(dist) == "uniform" ? LightDistribution::uniform : LightDistribution::latlong;
    PlotSeries series =
        make_series(std::string(dist == std::string("uniform") ? "uniform (spherical Fibonacci)"
                                                               : "lat-long (evenly spaced)"),
                    "line");
    for (int n : counts) {
      PlainEstimate e;
      try {
        e = estimate_on(ctx, "shadowmap-ao",
                        {{"lights", n}, {"resolution", map}, {"distribution", dist}}, scene, g);
      } catch (const EstimatorUnavailable& x) {
        r.notes.push_back(std::string("shadowmap-ao: skipped, ") + x.what());
        r.checks = lights_checks(numbers);
        return r;
      }
      const Metrics m = score_against(ctx, scene, view, w, h, accessibility, e.ao, all);
      const double share = polar_share(light_directions(n, d, false, 7));
      (d == LightDistribution::uniform ? numbers.uniform_rmse : numbers.latlong_rmse)
          .push_back(m.rmse);
      (d == LightDistribution::uniform ? numbers.uniform_polar : numbers.latlong_polar) = share;
      series.x.push_back(n);
      series.y.push_back(m.rmse);
      r.table.add({dist, std::to_string(n), std::to_string(map), std::to_string(w),
                   std::to_string(h), fmt(share), fmt(m.rmse), fmt(m.rmse_excess), fmt(m.bias),
                   fmt(e.frame_ms)});
    }
    plot.series.push_back(series);
  }
  render_plot(plot, ctx.path("gpugems-lights.png"));
  r.images = {"gpugems-lights.png"};
  r.checks = lights_checks(numbers);
  r.measured = "shadowmap-ao (per pixel, uniform weighting, lights on the whole sphere, " +
               std::to_string(map) + "² maps, seed 7) on elephant/main at " + std::to_string(w) +
               "x" + std::to_string(h) + " with " + std::to_string(counts.front()) + " to " +
               std::to_string(counts.back()) +
               " lights, uniform and lat-long (poles at ±Y, straight above the model), against "
               "the uniform-weighted reference (" +
               std::to_string(ctx.session->reference_spec().spp) +
               " spp); polar share = lights within 30° of ±Y.";
  r.notes.push_back(
      "both placements are deterministic lattices: the uniform one's error is its lattice "
      "discretisation plus the shadow maps' (resolution, bias), which flattens it at many lights; "
      "lat-long's adds the bias of weighting every ring equally.");
  return r;
}

}  // namespace aoeval::figures
