// The spatial index over the trees' large occluders (issue 45): at the exact cull (2^-26) the
// product of eq. 7-8 over the visited trees is bit-equal to the loop over every tree; at a coarse
// cull it is brighter by at most the sum of the skipped trees' occlusion bound; every tree within
// its radius of influence is visited, in increasing order.
#include "estimators/tree_proxies/occluder_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "base/testing/test_temp_dir.h"
#include "estimators/tree_proxies/testing_pixels.h"
#include "estimators/tree_proxies/tree_scene.h"
#include "scenes/testing_forest.h"

namespace aoeval {
namespace {

namespace hm = hegeman;

// A sparse forest over a wide square (so that the exact cull, r / sqrt(2^-25) ~ 5800 r, skips
// most trees from any point) with a dense clump at the origin: spheres and tilted ellipsoids.
std::vector<hm::UnitMap> forest(size_t n, float extent) {
  std::mt19937 rng(45);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<hm::UnitMap> maps;
  for (size_t t = 0; t < n; ++t) {
    Ellipsoid e;
    const float spread = t % 4 == 0 ? 40.0f : extent;
    e.center = glm::vec3(spread * u(rng), 3.0f + u(rng), spread * u(rng));
    const float r = 2.0f + u(rng);
    e.radii = t % 3 == 0 ? glm::vec3(r) : glm::vec3(r, 1.5f * r, 0.6f * r);
    const float a = 1.5f * u(rng);
    e.axes = glm::mat3(glm::vec3(std::cos(a), 0.0f, std::sin(a)), glm::vec3(0, 1, 0),
                       glm::vec3(-std::sin(a), 0.0f, std::cos(a)));
    maps.push_back(hm::make_unit_map(e));
  }
  return maps;
}

using testutil::Pixel;
std::vector<Pixel> pixels(size_t count, float extent) {
  return testutil::random_pixels(count, extent, 60.0f, 0.5f, 0.5f, 1.0f);
}

float every_tree(const std::vector<hm::UnitMap>& maps, const Pixel& p) {
  float v = 1.0f;
  for (const hm::UnitMap& m : maps) v *= hm::large_occluder_visibility(p.x, p.n, m, true);
  return v;
}

float through_index(const OccluderIndex& index, const std::vector<hm::UnitMap>& maps,
                    const Pixel& p, size_t* visited = nullptr) {
  float v = 1.0f;
  index.visit(p.x, [&](uint32_t t) {
    v *= hm::large_occluder_visibility(p.x, p.n, maps[t], true);
    if (visited) ++*visited;
  });
  return v;
}

TEST(OccluderIndex, ExactCullIsBitEqualToEveryTree) {
  const float extent = 60000.0f;
  const auto maps = forest(400, extent);
  OccluderIndex index;
  index.build(maps, kExactCull);
  ASSERT_FALSE(index.covers_all());
  size_t visited = 0, darker = 0;
  for (const Pixel& p : pixels(2000, extent)) {
    const float all = every_tree(maps, p);
    EXPECT_EQ(through_index(index, maps, p, &visited), all) << p.x.x << " " << p.x.z;
    darker += all < 1.0f;
  }
  EXPECT_LT(visited, 2000u * 400u / 4u);  // the index skips most trees ...
  EXPECT_GT(darker, 1000u);               // ... and the answers are not trivially 1
}

TEST(OccluderIndex, CoarseCullIsBrighterByAtMostTheSkippedOcclusion) {
  const float extent = 200.0f;
  const auto maps = forest(600, extent);
  const double eps = 1e-3;
  OccluderIndex index;
  index.build(maps, eps);
  size_t visited = 0;
  for (const Pixel& p : pixels(1000, extent)) {
    double skipped = 0.0;  // sum of the skipped trees' bound r_max^2 / (2 d^2)
    for (const hm::UnitMap& m : maps) {
      const glm::vec3 q = m.center - p.x;
      const double d2 = glm::dot(q, q), r2 = double(m.max_radius) * m.max_radius;
      if (r2 / (2.0 * d2) < eps) skipped += r2 / (2.0 * d2);
    }
    const float all = every_tree(maps, p), culled = through_index(index, maps, p, &visited);
    EXPECT_GE(culled, all * (1.0f - 1e-5f));
    EXPECT_LE(culled - all, skipped + 1e-5) << p.x.x << " " << p.x.z;
  }
  EXPECT_LT(visited, 1000u * 600u / 4u);
}

TEST(OccluderIndex, VisitsEveryTreeWithinReachInOrder) {
  const auto maps = forest(500, 300.0f);
  const double eps = 1e-3;
  OccluderIndex index;
  index.build(maps, eps);
  for (const Pixel& p : pixels(300, 300.0f)) {
    std::vector<uint32_t> seen;
    index.visit(p.x, [&](uint32_t t) { seen.push_back(t); });
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    std::vector<uint32_t> expected;
    for (uint32_t t = 0; t < maps.size(); ++t) {
      const glm::vec3 q = maps[t].center - p.x;
      const double d2 = glm::dot(q, q), r2 = double(maps[t].max_radius) * maps[t].max_radius;
      if (d2 <= r2 / (2.0 * eps) * (1.0 - 1e-6)) expected.push_back(t);
      // (trees within float rounding of the radius may go either way)
      if (std::fabs(d2 - r2 / (2.0 * eps)) < 1e-4 * d2) expected.erase(expected.end() - 1);
    }
    for (uint32_t t : expected) EXPECT_TRUE(std::binary_search(seen.begin(), seen.end(), t)) << t;
  }
}

// Through TreeScene on the small test forest: cull_occlusion 0 (every tree) and the default give
// the same bits for a ground pixel anywhere.
TEST(OccluderIndex, TreeSceneDefaultCullEqualsEveryTree) {
  const Scene s = load_scene_file(testutil::write_small_forest(testutil::test_temp_dir("cull")));
  TreeSceneOptions options{.proxy = ProxyOptions{},
                           .prefer_scene = true,
                           .horizon = true,
                           .grass_ground = false,
                           .blade_height = 0.0};
  TreeScene exact, all;
  exact.prepare(s, options);
  options.cull = 0.0;
  all.prepare(s, options);
  for (const Pixel& p : pixels(500, 30.0f))
    EXPECT_EQ(exact.others(p.x, p.n, -1), all.others(p.x, p.n, -1));
}

}  // namespace
}  // namespace aoeval
