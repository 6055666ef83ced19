// The checks of the engine teams' figures (figures_engine.h) and the depth-edge mask they split
// pixels by.
#include <algorithm>
#include <cmath>

#include "base/summary.h"
#include "harness/figures/figure_timing.h"
#include "harness/figures/figures_engine.h"

namespace aoeval::figures {

std::vector<uint8_t> depth_edge_mask(const GBuffer& g) {
  std::vector<uint8_t> edge(g.pixel_count(), 0);
  for (int j = 0; j < g.height; ++j) {
    for (int i = 0; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      if (!g.covered(p)) continue;
      const float zp = g.depth[p];
      for (int dj = -kEdgeRadius; dj <= kEdgeRadius && !edge[p]; ++dj) {
        for (int di = -kEdgeRadius; di <= kEdgeRadius; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= g.width || y >= g.height) continue;
          const size_t q = g.index(x, y);
          if (!g.covered(q) ||
              std::abs(g.depth[q] - zp) > kEdgeDepthJump * std::max(zp, g.depth[q])) {
            edge[p] = 1;
            break;
          }
        }
      }
    }
  }
  return edge;
}

std::vector<Check> half_resolution_checks(const HalfResNumbers& n) {
  std::vector<Check> checks;
  constexpr double kSpeedup = 0.6, kInterior = 0.01;
  std::string times;
  bool faster = !n.times.empty();
  for (const HalfResTimes& t : n.times) {
    const double p = p_slower(t.full_ms, t.half_ms, 1.0 / kSpeedup);
    faster = faster && p < kTimingAlpha;
    times += (times.empty() ? "" : "; ") + t.estimator + " full " + fmt(median(t.full_ms), 3) +
             " ms, half " + fmt(median(t.half_ms), 3) + " ms (" + p_text(p) + ")";
  }
  checks.push_back(
      {"half resolution saves time: each estimator's half-resolution AO time is "
       "below 0.6 x its full-resolution time (rank test over interleaved rounds)",
       faster, times});
  std::string interior, edges;
  bool interior_ok = !n.scores.empty(), edges_ok = !n.scores.empty();
  double worst = -1e300;
  for (const HalfResScore& s : n.scores) {
    const double di = s.half_interior - s.full_interior, de = s.half_edge - s.full_edge;
    interior_ok = interior_ok && di <= kInterior;
    edges_ok = edges_ok && de > di;
    worst = std::max(worst, di);
    interior += (interior.empty() ? "" : "; ") + s.estimator + " " + s.scene + " " + fmt(di, 3);
    edges += (edges.empty() ? "" : "; ") + s.estimator + " " + s.scene + " edge " + fmt(de, 3) +
             " vs interior " + fmt(di, 3);
  }
  checks.push_back(
      {"interior pixels keep their accuracy: half resolution raises the interior "
       "rmse_excess by at most 0.01 for every estimator and scene",
       interior_ok, "increase: " + interior});
  checks.push_back(
      {"the cost sits at depth edges: for every estimator and scene the edge pixels' "
       "rmse_excess grows more than the interior pixels' at half resolution",
       edges_ok, edges});
  return checks;
}

ThicknessChoice choose_thickness(const ThicknessNumbers& n) {
  ThicknessChoice best{0.0, 1e300};
  for (size_t t = 0; t < n.thickness.size(); ++t) {
    double worst = 0.0;
    for (const auto& e : n.error) {
      const double own = *std::min_element(e.begin(), e.end());
      worst = std::max(worst, own > 0.0 ? e[t] / own : (e[t] > 0.0 ? 1e300 : 1.0));
    }
    if (worst < best.worst_ratio) best = {n.thickness[t], worst};
  }
  return best;
}

std::vector<Check> gtao_thickness_checks(const ThicknessNumbers& n) {
  std::vector<Check> checks;
  constexpr double kGain = 0.03, kServe = 1.05;
  std::string gains;
  bool helps = false, every_thin = true;
  for (size_t s = 0; s < n.scenes.size(); ++s) {
    if (!n.thin[s]) continue;
    const auto& e = n.error[s];
    const double best = *std::min_element(e.begin(), e.end());
    const double gain = e.front() > 0.0 ? 1.0 - best / e.front() : 0.0;
    helps = true;
    every_thin = every_thin && gain >= kGain;
    gains += (gains.empty() ? "" : "; ") + n.scenes[s] + " " + fmt(100.0 * gain, 3) + " %";
  }
  checks.push_back(
      {"thickness helps thin occluders: on every thin scene the best thickness "
       "lowers rmse_excess by at least 3 % against thickness 0 (off)",
       helps && every_thin, "reduction at the scene's best: " + gains});
  const ThicknessChoice c = choose_thickness(n);
  std::string at;
  for (size_t s = 0; s < n.scenes.size(); ++s) {
    const auto& e = n.error[s];
    const size_t t = static_cast<size_t>(
        std::find(n.thickness.begin(), n.thickness.end(), c.thickness) - n.thickness.begin());
    at += (at.empty() ? "" : "; ") + n.scenes[s] + " " + fmt(e[t], 3) + " (best " +
          fmt(*std::min_element(e.begin(), e.end()), 3) + ")";
  }
  checks.push_back(
      {"one default serves thin and thick scenes: at the thickness with the least "
       "worst ratio, every scene's rmse_excess is within 5 % of its own best",
       !n.error.empty() && c.worst_ratio <= kServe,
       "thickness " + fmt(c.thickness, 3) + ", worst ratio " + fmt(c.worst_ratio, 4) + ": " + at});
  checks.push_back({"gtao's declared default thickness is that thickness",
                    !n.error.empty() && std::abs(n.declared_default - c.thickness) < 1e-9,
                    "declared " + fmt(n.declared_default, 3) + ", chosen " + fmt(c.thickness, 3)});
  return checks;
}

}  // namespace aoeval::figures
