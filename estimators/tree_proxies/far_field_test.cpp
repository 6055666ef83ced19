// The far-field term (far_field.h): a far cluster of identical spheres aggregated is within the
// derived bound of the exact product; angle 0 keeps today's bits; a forest's far field stays
// near the exact product while evaluating fewer occluders.
#include "estimators/tree_proxies/far_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "base/testing/test_temp_dir.h"
#include "estimators/tree_proxies/testing_pixels.h"
#include "estimators/tree_proxies/tree_scene.h"
#include "scenes/testing_forest.h"

namespace aoeval {
namespace {

namespace hm = hegeman;

hm::UnitMap sphere(const glm::vec3& c, float r) {
  return testutil::sphere_map(c, r);
}

// 64 identical spheres of radius r in a ball of radius rho around `centre` (centred, so their
// centroid is `centre` to float rounding), seen from the origin at distance d = |centre|.
std::vector<hm::UnitMap> cluster(const glm::vec3& centre, float rho, float r) {
  std::mt19937 rng(45);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> offsets;
  while (offsets.size() < 32) {
    const glm::vec3 p(u(rng), u(rng), u(rng));
    if (glm::dot(p, p) <= 1.0f) offsets.push_back(p * (rho - r));
  }
  std::vector<hm::UnitMap> maps;
  for (const glm::vec3& p : offsets) {  // +p and -p: the centroid is exactly `centre`
    maps.push_back(sphere(centre + p, r));
    maps.push_back(sphere(centre - p, r));
  }
  return maps;
}

TEST(FarField, FarClusterOfSpheresIsWithinTheDerivedBound) {
  const glm::vec3 x(0.0f), n(0.0f, 1.0f, 0.0f);
  const float r = 1.5f, rho = 6.0f;
  for (const float d : {15.0f, 30.0f, 60.0f, 200.0f}) {
    // Straight up from x, so every sphere is wholly above the horizon (h = 1) when d - rho > r.
    const auto maps = cluster(glm::vec3(0.0f, d, 0.0f), rho, r);
    double product = 1.0, sum = 0.0, sum2 = 0.0, amax = 0.0, spread2 = 0.0;
    for (const hm::UnitMap& m : maps) {
      const double a = 1.0 - hm::large_occluder_visibility(x, n, m, true);
      product *= 1.0 - a;
      sum += a;
      sum2 += a * a;
      amax = std::max(amax, a);
      const glm::vec3 q = m.center - glm::vec3(0.0f, d, 0.0f);
      spread2 = std::max(spread2, double(glm::dot(q, q)));
    }
    // a_N = n r^2 / (2 d^2); Taylor: |sum - a_N| <= 3 theta^2 / (1 - theta)^4 a_N, theta the
    // centres' spread over d; exp(-sum) - product in [0, sum2 / (2 (1 - amax))].
    const double a_n = double(maps.size()) * r * r / (2.0 * double(d) * d);
    const double theta = std::sqrt(spread2) / d;
    const double bound = 3.0 * theta * theta / std::pow(1.0 - theta, 4) * a_n +
                         sum2 / (2.0 * (1.0 - amax)) + 1e-6;  // + float rounding
    const float aggregate = aggregate_visibility(maps, x, n, true);
    EXPECT_NEAR(aggregate, std::exp(-a_n), 1e-6) << d;  // the closed form itself
    EXPECT_LE(std::fabs(double(aggregate) - product), bound) << d;
    // The bound is not trivially loose once theta is small, and the error is second order: at
    // d = 200 (theta = 0.025) below 1e-3 of the occlusion.
    if (d >= 60.0f) {
      EXPECT_GT(1.0 - product, 10.0 * bound) << d;
    }
    if (d >= 200.0f) {
      EXPECT_LT(std::fabs(double(aggregate) - product), 1e-3 * (1.0 - product));
    }
  }
}

using testutil::Pixel;
std::vector<Pixel> ground_pixels(size_t count, float extent) {
  return testutil::random_pixels(count, extent, 0.0f, 0.3f, 0.2f, 0.2f);
}

TreeSceneOptions options(double angle) {
  return {.proxy = ProxyOptions{},
          .prefer_scene = true,
          .horizon = true,
          .grass_ground = false,
          .blade_height = 0.0,
          .far_angle = angle};
}

// far_field_angle 0 is today's grid: the same bits as before the far field existed (cull 0, the
// loop over every tree in order, is bit-equal to the default cull: occluder_index_test.cpp).
TEST(FarField, AngleZeroKeepsTheExactBits) {
  const Scene s = load_scene_file(testutil::write_small_forest(testutil::test_temp_dir("far0")));
  TreeSceneOptions every = options(0.0);
  every.cull = 0.0;
  TreeScene exact, zero;
  exact.prepare(s, every);
  zero.prepare(s, options(0.0));
  for (const Pixel& p : ground_pixels(500, 30.0f))
    EXPECT_EQ(zero.others(p.x, p.n, -1), exact.others(p.x, p.n, -1));
}

// A forest of 2,000 spheres and ellipsoids on a plane: at angle 0.5 the far field stays within
// 0.02 of the exact product at every ground pixel (mean error below 0.005), and the error grows
// with the angle.
TEST(FarField, ForestStaysNearTheExactProduct) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<hm::UnitMap> maps;
  for (int t = 0; t < 2000; ++t) {
    Ellipsoid e;
    const float r = 2.0f + u(rng);
    e.center = glm::vec3(200.0f * u(rng), r + 1.0f, 200.0f * u(rng));
    e.radii = t % 2 ? glm::vec3(r) : glm::vec3(0.7f * r, 1.6f * r, 0.7f * r);
    maps.push_back(hm::make_unit_map(e));
  }
  double worst[2] = {0.0, 0.0}, mean[2] = {0.0, 0.0};
  const double angles[2] = {0.5, 0.9};
  const auto pixels = ground_pixels(300, 180.0f);
  for (int k = 0; k < 2; ++k) {
    FarField far;
    far.build(maps, 0.0, angles[k]);
    for (const Pixel& p : pixels) {
      double exact = 1.0;
      for (const hm::UnitMap& m : maps) exact *= hm::large_occluder_visibility(p.x, p.n, m, true);
      const double e = std::fabs(far.visibility(p.x, p.n, -1, true) - exact);
      worst[k] = std::max(worst[k], e);
      mean[k] += e / double(pixels.size());
    }
  }
  std::printf(
      "far field on 2,000 trees: angle 0.5 worst %.4f mean %.4f; 0.9 worst %.4f mean %.4f\n",
      worst[0], mean[0], worst[1], mean[1]);
  EXPECT_LT(worst[0], 0.03);
  EXPECT_LT(mean[0], 0.012);
  EXPECT_GT(mean[1], mean[0]);
}

// The tree a pixel belongs to is never part of an aggregate: skipping it gives the product of
// the others, also from outside its own envelope.
TEST(FarField, SkipLeavesOutOnlyThatTree) {
  std::vector<hm::UnitMap> maps;
  for (int t = 0; t < 40; ++t) maps.push_back(sphere(glm::vec3(10.0f * t, 3.0f, 0.0f), 2.0f));
  FarField far;
  far.build(maps, 0.0, 0.9);
  const glm::vec3 x(200.0f, 3.0f, 4.0f), n(0.0f, 0.0f, -1.0f);  // outside tree 20
  const float with = far.visibility(x, n, -1, true), without = far.visibility(x, n, 20, true);
  const float own = hm::large_occluder_visibility(x, n, maps[20], true);
  EXPECT_LT(own, 0.9f);
  EXPECT_NEAR(with / without, own, 2e-3f);
}

}  // namespace
}  // namespace aoeval
