// The engine figures' checks (figures_engine.h) pass and fail on numbers on both sides of their
// rules, the thickness choice is the least worst ratio, and the depth-edge mask marks exactly the
// pixels within kEdgeRadius of a depth jump or of the background.
#include <gtest/gtest.h>

#include "harness/figures/figure_checks_testing.h"
#include "harness/figures/figures_engine.h"

namespace aoeval::figures {
namespace {

using testing::expect_all;
using testing::times;

TEST(HalfResolutionChecks, PassAndFail) {
  HalfResNumbers good;
  good.times = {{"gtao", times(10.0), times(3.0)}};
  good.scores = {{"gtao", "bunny", 0.10, 0.14, 0.05, 0.055}};
  expect_all(half_resolution_checks(good), true, "good");
  HalfResNumbers bad;
  bad.times = {{"gtao", times(10.0), times(8.0)}};           // not 0.6x
  bad.scores = {{"gtao", "bunny", 0.10, 0.11, 0.05, 0.08}};  // interior +0.03 > edge +0.01
  expect_all(half_resolution_checks(bad), false, "bad");
  expect_all(half_resolution_checks({}), false, "nothing measured");
}

ThicknessNumbers thickness_numbers(double declared) {
  ThicknessNumbers n;
  n.thickness = {0.0, 0.5, 1.0};
  n.scenes = {"fence", "bunny"};
  n.thin = {true, false};
  n.error = {{0.20, 0.15, 0.16}, {0.10, 0.101, 0.12}};
  n.declared_default = declared;
  return n;
}

TEST(GtaoThicknessChecks, PassAndFail) {
  const ThicknessChoice c = choose_thickness(thickness_numbers(0.5));
  EXPECT_DOUBLE_EQ(c.thickness, 0.5);
  EXPECT_NEAR(c.worst_ratio, 1.01, 1e-12);
  expect_all(gtao_thickness_checks(thickness_numbers(0.5)), true, "good");
  ThicknessNumbers bad = thickness_numbers(1.0);
  // The fence gains 1 %; the wires want 0.5, which doubles bunny's error: no default serves.
  bad.scenes = {"fence", "wires", "bunny"};
  bad.thin = {true, true, false};
  bad.error = {{0.20, 0.198, 0.199}, {0.30, 0.10, 0.20}, {0.10, 0.20, 0.30}};
  expect_all(gtao_thickness_checks(bad), false, "bad");
}

TEST(DepthEdgeMask, MarksPixelsNearJumpsAndBackground) {
  GBuffer g;
  g.width = 12;
  g.height = 3;
  g.depth.assign(36, 1.0f);
  g.coverage.assign(36, 1.0f);
  for (int j = 0; j < 3; ++j) {
    for (int i = 6; i < 12; ++i) g.depth[g.index(i, j)] = 1.02f;  // 2 %: no edge
    g.depth[g.index(0, j)] = 2.0f;                                // a jump at column 0 | 1
  }
  g.coverage[g.index(11, 1)] = 0.0f;  // background at column 11
  const std::vector<uint8_t> e = depth_edge_mask(g);
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 12; ++i) {
      const bool expected = (i <= 2) || (i >= 9 && !(i == 11 && j == 1));
      EXPECT_EQ(e[g.index(i, j)] != 0, expected) << i << "," << j;
    }
  }
}

}  // namespace
}  // namespace aoeval::figures
