// The shared far field (far_cache.h): the same trees and parameters build once and later prepares
// get that build; a moved tree or a changed parameter builds again, and every field handed out has
// the bits a fresh, uncached build of its own input has.
#include "estimators/tree_proxies/far_cache.h"

#include <gtest/gtest.h>

#include "estimators/tree_proxies/testing_pixels.h"

namespace aoeval {
namespace {

// 12 x 12 = 144 trees, above FarGrid::kMinTrees, so a grid is built.
FarFieldsInput forest_input() {
  FarFieldsInput in;
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 12; ++k)
      in.occluders.push_back(
          testutil::sphere_map(glm::vec3(-22.0f + 4.0f * i, 3.0f, -22.0f + 4.0f * k), 1.5f));
  in.region.lower = glm::vec3(-30.0f, 0.0f, -30.0f);
  in.region.upper = glm::vec3(30.0f, 8.0f, 30.0f);
  in.cull = 0.0;
  in.angle = 0.7;
  in.cell = 4.0;
  in.near = 2.0;
  in.horizon = true;
  return in;
}

// Visibility at pixels over the forest floor, through the grid where it covers them.
std::vector<float> shade(const FarFields& f) {
  std::vector<float> out;
  for (const testutil::Pixel& p : testutil::random_pixels(400, 24.0f, 0.0f, 0.3f, 0.5f, 0.4f))
    out.push_back(f.grid.covers(p.x) ? f.grid.visibility(p.x, p.n, -1)
                                     : f.far.visibility(p.x, p.n, -1, true));
  return out;
}

std::vector<float> shade_uncached(const FarFieldsInput& in) {
  FarFields f;
  f.far.build(in.occluders, in.cull, in.angle);
  f.grid.build(in.occluders, f.far, in.region, in.cell, in.near, in.horizon);
  EXPECT_GT(f.grid.nodes(), 0u);
  return shade(f);
}

TEST(FarCache, TheSameTreesBuildOnceAndAMovedTreeBuildsItsOwn) {
  const FarFieldsInput in = forest_input();
  const size_t before = far_fields_builds();
  const auto first = shared_far_fields(in);
  EXPECT_EQ(far_fields_builds(), before + 1);
  const auto again = shared_far_fields(forest_input());  // an equal input, built anew
  EXPECT_EQ(again.get(), first.get());
  EXPECT_EQ(far_fields_builds(), before + 1);
  EXPECT_EQ(shade(*first), shade_uncached(in));

  FarFieldsInput moved = in;
  moved.occluders[70] = testutil::sphere_map(moved.occluders[70].center + glm::vec3(0.5f), 1.5f);
  const auto other = shared_far_fields(moved);
  EXPECT_NE(other.get(), first.get());
  EXPECT_EQ(far_fields_builds(), before + 2);
  EXPECT_EQ(shade(*other), shade_uncached(moved));
  EXPECT_NE(shade(*other), shade(*first));  // the move is visible: a stale field would fail above
}

TEST(FarCache, EveryParameterIsPartOfTheKey) {
  const FarFieldsInput base = forest_input();
  const auto first = shared_far_fields(base);
  std::vector<FarFieldsInput> changed(6, base);
  changed[0].cull = 0.01;
  changed[1].angle = 0.5;
  changed[2].cell = 3.0;
  changed[3].near = 3.0;
  changed[4].horizon = false;
  changed[5].region.upper.y = 9.0f;
  for (const FarFieldsInput& in : changed) {
    const size_t before = far_fields_builds();
    const auto f = shared_far_fields(in);
    EXPECT_NE(f.get(), first.get());
    EXPECT_EQ(far_fields_builds(), before + 1);
  }
}

}  // namespace
}  // namespace aoeval
