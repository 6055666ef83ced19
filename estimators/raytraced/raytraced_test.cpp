// raytraced: Monte-Carlo AO with Embree, checked on analytic scenes with known answers.
#include "estimators/raytraced/raytraced.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scenes/analytic_scenes.h"

namespace aoeval {
namespace {

EstimateResult run_raytraced(const Scene& s, const GBuffer& g, const nlohmann::json& overrides) {
  const EstimatorInfo e = raytraced_estimator();
  EmbreeScene es(s);
  auto est = e.create(resolve_params(e.name, e.params, overrides, "test"));
  return est->run({s, es, g});
}

double mean(const std::vector<float>& v) {
  double sum = 0.0;
  for (float x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

TEST(Raytraced, OpenPlaneIsOneAndABoxInteriorIsZero) {
  const Scene plane = scene_of({generated("floor", "plane", {{"size", {50, 50}}})});
  for (const char* w : {"cosine", "uniform"})
    for (float a : run_raytraced(plane, probe({0.2f, 0, 0.1f}, {0, 1, 0}, 16),
                                 {{"weighting", w}, {"rays", 32}})
                       .ao)
      EXPECT_EQ(a, 1.0f) << w;
  const Scene box = scene_of({generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}})});
  for (float a : run_raytraced(box, probe({0.3f, 0, 0.2f}, {0, 1, 0}, 16), {{"rays", 32}}).ao)
    EXPECT_EQ(a, 0.0f);
}

// A floor point at the foot of a tall wall: the wall fills the half-space x < 0, which holds half
// of the hemisphere's cosine-weighted (and uniform) measure, so AO = 1/2. The estimate over n =
// pixels x rays independent random directions has standard error sqrt(1/4 / n); 5 of them is the
// tolerance (unbounded definition, the default).
TEST(Raytraced, TheFootOfAWallIsHalfOccluded) {
  SceneObject floor = generated("floor", "plane", {{"size", {40, 40}}});
  SceneObject wall = generated("wall", "box", {{"size", {2, 40, 40}}}, {-1.0f, 0, 0});
  const Scene s = scene_of({std::move(floor), std::move(wall)});
  const int pixels = 256, rays = 64;
  for (const char* w : {"cosine", "uniform"}) {
    const EstimateResult r =
        run_raytraced(s, probe({1e-3f, 0, 0}, {0, 1, 0}, pixels),
                      {{"weighting", w}, {"rays", rays}, {"sampler", "random"}});
    const double tol = 5.0 * std::sqrt(0.25 / (pixels * rays));
    EXPECT_NEAR(mean(r.ao), 0.5, tol) << w;
    ASSERT_EQ(r.extra_channels.count("AO_stderr"), 1u);
  }
}

TEST(Raytraced, SameSeedSameBitsOtherSeedOtherBits) {
  SceneObject floor = generated("floor", "plane", {{"size", {40, 40}}});
  SceneObject wall = generated("wall", "box", {{"size", {2, 40, 40}}}, {-1.0f, 0, 0});
  const Scene s = scene_of({std::move(floor), std::move(wall)});
  const GBuffer g = probe({0.5f, 0, 0}, {0, 1, 0}, 32);
  const auto a = run_raytraced(s, g, {{"seed", 3}}).ao, b = run_raytraced(s, g, {{"seed", 3}}).ao,
             c = run_raytraced(s, g, {{"seed", 4}}).ao;
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

}  // namespace
}  // namespace aoeval
