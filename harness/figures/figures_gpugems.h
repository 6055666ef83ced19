// What the GPU Gems ch. 17 figures share (figures_gpugems.cpp, figures_gpugems_lights.cpp): an
// estimator run on any scene file against a given G-buffer (for scene variants whose surfaces are
// those of a corpus scene, so that the corpus scene's reference and masks apply), and the checks of
// gpugems-lights as a function of its numbers, so that a test can show them passing and failing.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/figures/figure.h"

namespace aoeval::figures {

struct PlainEstimate {
  std::vector<float> ao;
  double precompute_ms = 0.0, frame_ms = 0.0;
};
// prepare() (timed as precompute_ms) and one run() (frame_ms) of `estimator` on the scene `scene`
// (a corpus name or a scene file) with the G-buffer `g`. Throws EstimatorUnavailable as run_scored.
PlainEstimate estimate_on(FigureContext& ctx, const std::string& estimator,
                          const nlohmann::json& overrides, const std::string& scene,
                          const GBuffer& g);

// A copy of corpus scene `scene` whose ground planes (role ground, generator plane) have their
// `subdivisions` parameter set to `subdivisions`, written under <out>/scenes/; returns its path.
// Only the tessellation changes: the surfaces are the same, so the corpus scene's G-buffer and
// reference hold for it.
std::string floor_variant(FigureContext& ctx, const std::string& scene, int subdivisions);

// gpugems-lights' numbers, per light count (ascending), and its checks.
struct LightsNumbers {
  std::vector<int> lights;
  std::vector<double> uniform_rmse, latlong_rmse;
  double uniform_polar = 0.0, latlong_polar = 0.0;  // share within 30° of ±Y at the largest count
};
std::vector<Check> lights_checks(const LightsNumbers& n);
// The figure itself (figures_gpugems_lights.cpp).
FigureResult gpugems_lights(FigureContext& ctx);

}  // namespace aoeval::figures
