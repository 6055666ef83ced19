// The precomputed far field (far_grid.h): a far regular cluster is interpolated within the derived
// bound (and reading the neighbouring cell is not); a near radius that holds every tree keeps the
// bits of the product over the trees.
#include "estimators/tree_proxies/far_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "base/errors.h"
#include "estimators/tree_proxies/far_field.h"
#include "estimators/tree_proxies/testing_pixels.h"

namespace aoeval {
namespace {

namespace hm = hegeman;

hm::UnitMap sphere(const glm::vec3& c, float r) {
  return testutil::sphere_map(c, r);
}

Bounds box(const glm::vec3& lo, const glm::vec3& hi) {
  Bounds b;
  b.lower = lo;
  b.upper = hi;
  return b;
}

// A 12 x 12 lattice of spheres of radius r, 3 apart, at height 10 over the square [-16.5, 16.5]:
// every pixel below at height 3 to 5 sees each wholly above its horizon (n up).
std::vector<hm::UnitMap> lattice(float r) {
  std::vector<hm::UnitMap> maps;
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 12; ++k)
      maps.push_back(sphere(glm::vec3(-16.5f + 3.0f * i, 10.0f, -16.5f + 3.0f * k), r));
  return maps;
}

// far_grid.h's bound for one cell: h^2 / 8 * sum_t (7 r^2 / (d^4 (1 - a)) + 3 r^4 / (d^6 (1 -
// a)^2)), d the tree's distance from the cell (its centre's distance from x less the cell's
// diagonal), a = r^2 / (2 d^2) its largest occlusion over the cell.
double interpolation_bound(const std::vector<hm::UnitMap>& maps, const glm::vec3& x, double h) {
  double sum = 0.0;
  for (const hm::UnitMap& m : maps) {
    const double d = glm::length(glm::dvec3(m.center) - glm::dvec3(x)) - std::sqrt(3.0) * h;
    const double r2 = static_cast<double>(m.max_radius) * m.max_radius;
    const double a = r2 / (2.0 * d * d);
    sum += 7.0 * r2 / (std::pow(d, 4) * (1.0 - a)) +
           3.0 * r2 * r2 / (std::pow(d, 6) * (1.0 - a) * (1.0 - a));
  }
  return h * h / 8.0 * sum;
}

TEST(FarGrid, FarRegularClusterIsWithinTheInterpolationBound) {
  const auto maps = lattice(1.0f);
  FarField far;
  far.build(maps, 0.0, 0.0);  // no aggregation: the nodes hold the exact sum
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  for (const double h : {1.0}) {  // 2 passes too, with a looser bound (d less 3.5)
    FarGrid grid;
    // Near radius 1: every tree is beyond its outer radius (r + 0.5) of every pixel.
    grid.build(maps, far, box(glm::vec3(-8.0f, 3.0f, -8.0f), glm::vec3(8.0f, 5.0f, 8.0f)), h, 1.0,
               true);
    std::mt19937 rng(45);
    std::uniform_real_distribution<float> u(-6.0f, 6.0f), v(3.0f, 5.0f);
    double worst = 0.0, shifted = 0.0;
    for (int p = 0; p < 2000; ++p) {
      const glm::vec3 x(u(rng), v(rng), u(rng));
      ASSERT_TRUE(grid.covers(x));
      double exact = 0.0;
      for (const hm::UnitMap& m : maps)
        exact -= std::log(static_cast<double>(hm::large_occluder_visibility(x, up, m, true)));
      const double bound = interpolation_bound(maps, x, h);
      const double error = std::fabs(grid.far_occlusion(x, up) - exact);
      EXPECT_LE(error, bound + 1e-6 * exact)
          << "h " << h << " at " << x.x << " " << x.y << " " << x.z;
      worst = std::max(worst, error / bound);
      // A planted wrong answer: the value one cell lower (an off-by-one in the cell index).
      const glm::vec3 over(x.x, x.y - static_cast<float>(h), x.z);
      if (grid.covers(over))
        shifted = std::max(shifted, std::fabs(grid.far_occlusion(over, up) - exact) / bound);
      EXPECT_NEAR(grid.visibility(x, up, -1), std::exp(-exact), bound + 1e-6);
    }
    std::printf("h %g: worst error / bound %.3f, one cell lower %.3f\n", h, worst, shifted);
    EXPECT_GT(worst, 0.02) << "h " << h << ": the bound is not vacuous";
    EXPECT_GT(shifted, 1.0) << "h " << h << ": the neighbouring cell fails the bound";
  }
}

TEST(FarGrid, NearRadiusHoldingEveryTreeKeepsTheExactBits) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f), y(3.0f, 6.0f), r(0.8f, 2.5f);
  std::vector<hm::UnitMap> maps;
  for (int t = 0; t < 120; ++t) maps.push_back(sphere(glm::vec3(u(rng), y(rng), u(rng)), r(rng)));
  FarField far;
  far.build(maps, 0.0, 0.7);
  FarGrid grid;
  // R/2 = 40 holds every tree from every pixel: the grid's far sums are 0, every tree exact.
  grid.build(maps, far, box(glm::vec3(-12.0f, 0.0f, -12.0f), glm::vec3(12.0f, 8.0f, 12.0f)), 2.0,
             80.0, true);
  std::uniform_real_distribution<float> tilt(-1.0f, 1.0f), h(0.0f, 8.0f);
  std::uniform_int_distribution<int> own(-1, 119);
  for (int p = 0; p < 2000; ++p) {
    const glm::vec3 x(u(rng), h(rng), u(rng));
    const glm::vec3 n = glm::normalize(glm::vec3(tilt(rng), tilt(rng) + 1.5f, tilt(rng)));
    const int skip = own(rng);
    float product = 1.0f;
    for (size_t t = 0; t < maps.size(); ++t)
      if (static_cast<int>(t) != skip)
        product *= hm::large_occluder_visibility(x, n, maps[t], true);
    ASSERT_TRUE(grid.covers(x));
    EXPECT_EQ(grid.far_occlusion(x, n), 0.0f);
    EXPECT_EQ(grid.visibility(x, n, skip), product);
  }
}

TEST(FarGrid, TooFineACellIsRefusedWithOneLine) {
  const auto maps = lattice(1.0f);
  FarField far;
  far.build(maps, 0.0, 0.7);
  FarGrid grid;
  try {
    grid.build(maps, far, box(glm::vec3(-40.0f), glm::vec3(40.0f)), 0.01, 2.0, true);
    FAIL() << "a grid of 10^11 nodes was built";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use a larger cell"), std::string::npos) << e.what();
  }
  // Fewer than kMinTrees trees: no grid at any cell.
  const std::vector<hm::UnitMap> few(maps.begin(), maps.begin() + 99);
  far.build(few, 0.0, 0.7);
  grid.build(few, far, box(glm::vec3(-40.0f), glm::vec3(40.0f)), 0.01, 2.0, true);
  EXPECT_FALSE(grid.covers(glm::vec3(0.0f)));
}

}  // namespace
}  // namespace aoeval
