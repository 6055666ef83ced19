// Every check of the Hegeman, Mendez and fig17-3 figures can pass and can fail: each figure's
// check function is fed synthetic numbers once where the claim holds (every check passes) and once
// where it does not (every check fails). Timing checks get synthetic repetitions: clearly ordered
// ones, and ones where the order is reversed, so the rank test decides both ways. (gpugems-lights:
// figures_gpugems_test.cpp.)
#include <gtest/gtest.h>

#include "harness/figures/figure_checks.h"
#include "harness/figures/figure_checks_testing.h"
#include "harness/figures/figure_timing.h"

namespace aoeval::figures {
namespace {

using testing::expect_all;
using testing::times;

TEST(FigureTiming, RankTestDecidesBothWaysAndScales) {
  const auto a = times(10.0), b = times(20.0);
  EXPECT_LT(p_slower(b, a), kTimingAlpha);
  EXPECT_GT(p_slower(a, b), 0.5);
  EXPECT_LT(p_faster(a, b), kTimingAlpha);
  // b is 2 x a: slower than 1.5 x a, not slower than 2.5 x a.
  EXPECT_LT(p_slower(b, a, 1.5), kTimingAlpha);
  EXPECT_GT(p_slower(b, a, 2.5), 0.5);
  // Identical samples: no decision either way.
  EXPECT_GT(p_slower(a, a), kTimingAlpha);
  EXPECT_GT(p_faster(a, a), kTimingAlpha);
  EXPECT_EQ(p_slower({}, a), 1.0);
}

TEST(FigureChecks, HegemanFig2) {
  Fig2Numbers good;
  good.scenes = {"sphere-uniform", "sphere-uniform-dense", "tree-apple", "tree-poplar"};
  good.derived = good.best = good.volume = {{0.05, 0.9}, {0.06, 0.9}, {0.2, 0.7}, {0.1, 0.8}};
  good.best_scale = {1, 1, 1, 1};
  expect_all(hegeman_fig2_checks(good), true, "fig2 good");
  Fig2Numbers bad = good;
  bad.best = {{0.11, 0.5}, {0.12, 0.4}, {0.2, -0.1}, {0.1, 0.2}};
  expect_all(hegeman_fig2_checks(bad), false, "fig2 bad");
  // The apple's error being large is not evidence for the claim: no check rewards it.
  Fig2Numbers worse_apple = good;
  worse_apple.best[2].rmse = 0.9;
  EXPECT_EQ(hegeman_fig2_checks(worse_apple)[0].passed, true);
  expect_all(hegeman_fig2_checks(Fig2Numbers{}), false, "fig2 not run");
}

TEST(FigureChecks, HegemanFig8) {
  expect_all(hegeman_fig8_checks({0.05, 0.1, 0.08, 0.1}), true, "fig8 good");
  expect_all(hegeman_fig8_checks({0.2, 0.1, 0.08, 0.01}), false, "fig8 bad");
}

TEST(FigureChecks, HegemanFig12) {
  Fig12Numbers good{{"overview", "meadow"},
                    {{0.1, 0.2, 0.3}, {0.1, 0.2, 0.3}},
                    {{0.6, 0.3, 0.0}, {0.6, 0.3, 0.0}}};
  expect_all(hegeman_fig12_checks(good), true, "fig12 good");
  Fig12Numbers bad{{"overview", "meadow"},
                   {{0.4, 0.2, 0.3}, {0.4, 0.2, 0.3}},
                   {{0.1, 0.3, 0.0}, {0.1, 0.3, 0.0}}};
  expect_all(hegeman_fig12_checks(bad), false, "fig12 bad");
}

TEST(FigureChecks, HegemanThroughput) {
  // Paper ratios: ours / R-B throughput 0.79, ours / ambient 0.20 -> times 1 : 0.79 : 0.2.
  expect_all(hegeman_throughput_checks({times(10.0), times(7.9), times(2.0)}), true,
             "throughput good");
  // Reversed order and ratios far outside the bands (ours 10x faster than R-B, 50x ambient).
  expect_all(hegeman_throughput_checks({times(1.0), times(10.0), times(50.0)}), false,
             "throughput bad");
}

TEST(FigureChecks, MendezFig6) {
  Fig6Numbers good{{4, 16, 64},
                   {0.2, 0.1, 0.05},
                   {0.001, 0.001, 0.001},
                   {0.1, 0.05, 0.02},
                   {0.001, 0.001, 0.001}};
  expect_all(mendez_fig6_checks(good), true, "fig6 good");
  Fig6Numbers bad{{4, 16, 64},
                  {0.1, 0.05, 0.02},
                  {0.001, 0.001, 0.001},
                  {0.2, 0.1, 0.05},
                  {0.001, 0.001, 0.001}};
  expect_all(mendez_fig6_checks(bad), false, "fig6 bad");
}

TEST(FigureChecks, MendezFig7) {
  // The paper's 219 : 241 : 264 : 314.
  Fig7Numbers good{{0.2, 0.5, 1.0, 2.0},
                   {0.9, 0.8, 0.7, 0.6},
                   {times(21.9), times(24.1), times(26.4), times(31.4)}};
  expect_all(mendez_fig7_checks(good), true, "fig7 good");
  // Brighter with dmax, and faster (a step 20 % faster; 2.0 at half the time of 0.2).
  Fig7Numbers bad{{0.2, 0.5, 1.0, 2.0},
                  {0.6, 0.7, 0.8, 0.9},
                  {times(20.0), times(16.0), times(12.0), times(10.0)}};
  expect_all(mendez_fig7_checks(bad), false, "fig7 bad");
  // Equal times at every dmax: no evidence that time grows, so the timing check fails; it prints
  // its p-values.
  Fig7Numbers flat = good;
  flat.ms = {times(20.0), times(20.0), times(20.0), times(20.0)};
  const auto c = mendez_fig7_checks(flat);
  EXPECT_NE(c[1].measured.find("p = "), std::string::npos);
  EXPECT_FALSE(c[1].passed);
}

TEST(FigureChecks, GpugemsFig17_3) {
  Fig17Numbers good;
  good.have_fine = good.have_coarse = good.have_shadowmap = true;
  good.fine_model_r = 0.9, good.fine_shadow = 0.22, good.coarse_shadow = 0.01;
  good.ref_shadow = 0.23, good.shadowmap_model_r = 0.9, good.shadowmap_shadow = 0.22;
  expect_all(gpugems_fig17_checks(good), true, "fig17-3 good");
  Fig17Numbers bad = good;
  bad.fine_model_r = 0.5, bad.fine_shadow = 0.02, bad.shadowmap_model_r = 0.5;
  expect_all(gpugems_fig17_checks(bad), false, "fig17-3 bad");
}

TEST(FigureChecks, EqualTime) {
  EqualTimeNumbers good;
  good.scenes = 4;
  good.winners = {"bunny: gtao", "dragon: gtao", "room: gtao", "cornell-box: hbao-split"};
  good.gtao_bent_excess = {4.0, 6.5, 3.2, 9.9};
  expect_all(equal_time_checks(good), true, "equal-time good");
  EqualTimeNumbers bad = good;
  bad.timing_misses = {"raymarch-ssao on bunny 9.1 ms vs 3.0"};
  bad.winners = {"bunny: gtao", "dragon: raymarch-ssao", "room: hbao-split",
                 "cornell-box: hbao-split"};
  bad.gtao_bent_excess = {4.0, 16.0, 3.2, 9.9};
  expect_all(equal_time_checks(bad), false, "equal-time bad");
}

TEST(FigureChecks, DimitrovFig6) {
  expect_all(dimitrov_fig6_checks({{0.9, 0.8, 0.7}, {0.01, 0.02, 0.03}}), true, "dfig6 good");
  expect_all(dimitrov_fig6_checks({{0.7, 0.8, 0.9}, {0.03, 0.02, 0.01}}), false, "dfig6 bad");
}

TEST(FigureChecks, DimitrovFig7) {
  expect_all(dimitrov_fig7_checks({0.1, 0.05, 0.03, times(2.0), times(20.0)}), true, "dfig7 good");
  // Nd 16 only 2x Nd 1 (not proportional) and RMSE rising.
  expect_all(dimitrov_fig7_checks({0.03, 0.05, 0.1, times(2.0), times(4.0)}), false, "dfig7 bad");
}

TEST(FigureChecks, DimitrovFig11) {
  expect_all(dimitrov_fig11_checks(
                 {{0.1, 0.08, 0.06, 0.05}, {times(5.0), times(10.0), times(15.0), times(40.0)}}),
             true, "dfig11 good");
  expect_all(dimitrov_fig11_checks(
                 {{0.05, 0.06, 0.08, 0.1}, {times(40.0), times(15.0), times(10.0), times(5.0)}}),
             false, "dfig11 bad");
}

TEST(FigureChecks, DimitrovFig12) {
  expect_all(dimitrov_fig12_checks({{4, 8}, {0.05, 0.03}, {0.1, 0.06}}), true, "dfig12 good");
  expect_all(dimitrov_fig12_checks({{4, 8}, {0.1, 0.06}, {0.05, 0.03}}), false, "dfig12 bad");
}

TEST(FigureChecks, DimitrovTable1) {
  // The paper's 640x480 and 1600x1153 rows, as ratios: HO/NO 1.53 and 1.06, HO grows 5.5x.
  Table1Numbers good;
  good.ho = {times(7.16), times(39.66)};
  good.no = {times(4.67), times(37.41)};
  good.blur = {times(0.71), times(4.35)};
  good.geo = {times(4.02), times(6.68)};
  good.paper_ho_over_no = {7.16 / 4.67, 39.66 / 37.41};
  good.paper_ho = {7.16, 39.66};
  good.pixels = good.paper_pixels = {640.0 * 480, 1600.0 * 1153};
  expect_all(dimitrov_table1_checks(good), true, "table1 good");
  // HO 5x NO, blur the dearest pass, HO flat with resolution while the geometry grows.
  Table1Numbers bad = good;
  bad.ho = {times(20.0), times(20.0)};
  bad.no = {times(4.0), times(4.0)};
  bad.blur = {times(30.0), times(30.0)};
  bad.geo = {times(1.0), times(10.0)};
  expect_all(dimitrov_table1_checks(bad), false, "table1 bad");
}

}  // namespace
}  // namespace aoeval::figures
