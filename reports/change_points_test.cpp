// E-Divisive change points (change_points.h) on synthetic series: known steps are found where they
// are, and pure noise raises few false alarms, counted and printed (the README quotes them; rerun
// with `build/reports/dashboard_test --gtest_filter='ChangePoints.*'`).
#include "reports/change_points.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace aoeval {
namespace {

ChangePointOptions quality(double absolute, double relative = 0.05) {
  ChangePointOptions o;
  o.test = ChangePointOptions::Test::tolerance;
  o.absolute = absolute;
  o.relative = relative;
  return o;
}

ChangePointOptions timing(double relative) {
  ChangePointOptions o;
  o.test = ChangePointOptions::Test::permutation;
  o.relative = relative;
  o.alpha = 0.01;
  return o;
}

TEST(ChangePoints, ADeterministicStepIsFoundAtItsRunWithItsLevels) {
  std::vector<double> s(8, 0.0210);
  for (size_t i = 4; i < 8; ++i) s[i] = 0.0341;
  const auto steps = change_points(s, quality(1e-4));
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].index, 4u);
  EXPECT_DOUBLE_EQ(steps[0].before, 0.0210);
  EXPECT_DOUBLE_EQ(steps[0].after, 0.0341);
  // A step at the newest run is found too (quality segments may be one run long).
  s.assign(8, 0.5);
  s[7] = 0.45;
  const auto last = change_points(s, quality(0.005, 0.0));
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].index, 7u);
  // Below the tolerance: none.
  s[7] = 0.497;
  EXPECT_TRUE(change_points(s, quality(0.005, 0.0)).empty());
}

TEST(ChangePoints, SeveralStepsEachReportTheirOwnLevelsAndOneRunAwayIsNoStep) {
  const std::vector<double> s = {1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 9, 9, 3, 3};
  const auto steps = change_points(s, quality(0.1, 0.0));
  ASSERT_EQ(steps.size(), 4u);
  EXPECT_EQ(steps[0].index, 3u);
  EXPECT_EQ(steps[1].index, 7u);
  EXPECT_EQ(steps[2].index, 10u);  // two runs up...
  EXPECT_EQ(steps[3].index, 12u);  // ...and back down
  EXPECT_DOUBLE_EQ(steps[0].before, 1.0);
  EXPECT_DOUBLE_EQ(steps[0].after, 2.0);
  EXPECT_DOUBLE_EQ(steps[2].after, 9.0);
  EXPECT_DOUBLE_EQ(steps[3].after, 3.0);
  // A single run away inside a level is an outlier, not a new level: the energy statistic of
  // every split around it is 0 (change_points.h).
  const auto spike = change_points({1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 9, 3, 3}, quality(0.1, 0.0));
  ASSERT_EQ(spike.size(), 2u);
  EXPECT_EQ(spike[1].index, 7u);
  EXPECT_THROW(change_points({1.0, NAN}, quality(0.1)), std::invalid_argument);
  EXPECT_TRUE(change_points({}, quality(0.1)).empty());
  EXPECT_TRUE(change_points({1.0}, quality(0.1)).empty());
}

TEST(ChangePoints, ATimingStepIsFoundThroughNoiseAndOneSlowRunIsNot) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);  // 5 % run-to-run scatter
  std::vector<double> s;
  for (int i = 0; i < 30; ++i) s.push_back(25.0 * (i >= 12 ? 1.8 : 1.0) * std::exp(noise(rng)));
  const auto steps = change_points(s, timing(0.10));
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].index, 12u);
  EXPECT_NEAR(steps[0].after / steps[0].before, 1.8, 0.1);
  EXPECT_LE(steps[0].p, 0.01);
  // One slow run (79 ms among 23-32 ms), anywhere, the newest included: no step.
  for (size_t at : {size_t{0}, size_t{5}, size_t{29}}) {
    std::vector<double> flat;
    for (int i = 0; i < 30; ++i) flat.push_back(23.0 + 9.0 * ((i * 7) % 10) / 10.0);
    flat[at] = 79.0;
    EXPECT_TRUE(change_points(flat, timing(0.10)).empty()) << at;
  }
  // A real but small drift stays below the magnitude floor.
  for (size_t i = 0; i < s.size(); ++i) s[i] = 25.0 * (i >= 12 ? 1.05 : 1.0);
  EXPECT_TRUE(change_points(s, timing(0.10)).empty());
}

// Series with no step at all: how often does any step get reported? Counted over many series and
// printed; the bounds are a few binomial standard errors above the rates the method is built for.
TEST(ChangePoints, PureNoiseFalseAlarmRates) {
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int kSeries = 400;
  // Times: log-normal scatter of 10 % per run; the permutation test alone (no magnitude floor)
  // should alarm in about alpha = 1 % of series; with the shipped floor (time_relative 0.60) and
  // 10 % of runs 2.5x slower (a shared machine's hiccups), almost never.
  for (size_t n : {size_t{8}, size_t{30}}) {
    int test_only = 0, heavy_with_floor = 0;
    for (int k = 0; k < kSeries; ++k) {
      std::vector<double> plain, heavy;
      for (size_t i = 0; i < n; ++i) {
        plain.push_back(25.0 * std::exp(0.1 * gauss(rng)));
        heavy.push_back(plain.back() * (uniform(rng) < 0.1 ? 2.5 : 1.0));
      }
      test_only += !change_points(plain, timing(0.0)).empty();
      heavy_with_floor += !change_points(heavy, timing(0.60)).empty();
    }
    const double rate = static_cast<double>(test_only) / kSeries;
    const double heavy_rate = static_cast<double>(heavy_with_floor) / kSeries;
    std::printf(
        "times, %zu runs: false alarms %.2f %% (test alone), %.2f %% (outliers, floor 0.60)\n", n,
        100.0 * rate, 100.0 * heavy_rate);
    EXPECT_LE(rate, 0.01 + 4.0 * std::sqrt(0.01 * 0.99 / kSeries)) << n;
    EXPECT_LE(heavy_rate, 0.02) << n;
  }
  // Quality: scatter of a fifth of the tolerance (a reference re-rendered with other seeds): the
  // tolerance is five standard deviations away, so no alarm is expected.
  int quality_alarms = 0;
  for (int k = 0; k < kSeries; ++k) {
    std::vector<double> s;
    for (int i = 0; i < 30; ++i) s.push_back(0.02 + 0.2 * 0.001 * gauss(rng));
    quality_alarms += !change_points(s, quality(0.001, 0.0)).empty();
  }
  std::printf("quality, 30 runs, scatter tolerance/5: false alarms %.2f %%\n",
              100.0 * quality_alarms / kSeries);
  EXPECT_EQ(quality_alarms, 0);
}

}  // namespace
}  // namespace aoeval
