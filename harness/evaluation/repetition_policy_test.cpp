// The repetition policy (repetition_policy.h): the median's order-statistic interval and its
// coverage, a fixed count stays fixed, and an adaptive count stops as soon as the interval is
// within +-median_ci of the median, or at the maximum. Plain numbers, no clocks.
#include "harness/evaluation/repetition_policy.h"

#include <gtest/gtest.h>

#include "harness/evaluation/evaluation.h"

namespace aoeval {
namespace {

TEST(RepetitionPolicy, MedianIntervalIsTheOrderStatisticsInterval) {
  // Below 6 samples no interval reaches 95 %: the range, coverage 1 - 2^(1-n).
  const MedianInterval three = median_interval({12.0, 10.0, 11.0});
  EXPECT_EQ(three.lo, 10.0);
  EXPECT_EQ(three.hi, 12.0);
  EXPECT_DOUBLE_EQ(three.coverage, 0.75);
  EXPECT_DOUBLE_EQ(median_interval({1, 2, 3, 4, 5}).coverage, 0.9375);
  // 9 samples: [x(2), x(8)], coverage 1 - 2 * 10/512 = 0.9609.
  const MedianInterval nine = median_interval({9, 1, 8, 2, 7, 3, 6, 4, 5});
  EXPECT_EQ(nine.lo, 2.0);
  EXPECT_EQ(nine.hi, 8.0);
  EXPECT_NEAR(nine.coverage, 1.0 - 20.0 / 512.0, 1e-12);
  // 20 samples: [x(6), x(15)], coverage 0.9586.
  std::vector<double> twenty;
  for (int i = 1; i <= 20; ++i) twenty.push_back(i);
  const MedianInterval t = median_interval(twenty);
  EXPECT_EQ(t.lo, 6.0);
  EXPECT_EQ(t.hi, 15.0);
  EXPECT_NEAR(t.coverage, 0.9586, 1e-4);
}

TEST(RepetitionPolicy, FixedCountIsFixed) {
  TimingSpec fixed;  // repetitions 5, no maximum
  EXPECT_FALSE(enough_repetitions(fixed, {10, 10, 10, 10}));
  EXPECT_TRUE(enough_repetitions(fixed, {10, 30, 10, 50, 10}));
}

TEST(RepetitionPolicy, AdaptiveStopsWhenTheMediansIntervalIsNarrow) {
  TimingSpec adaptive;
  adaptive.repetitions = 3;
  adaptive.max_repetitions = 15;
  adaptive.median_ci = 0.05;
  EXPECT_FALSE(enough_repetitions(adaptive, {10.0, 10.1}));       // below the least
  EXPECT_TRUE(enough_repetitions(adaptive, {10.0, 10.4, 9.6}));   // all within +-5 %
  EXPECT_FALSE(enough_repetitions(adaptive, {10.0, 11.0, 9.6}));  // 11 is 10 % above
  // One slow repetition among steady ones: at 9 the interval [x(2), x(8)] drops it.
  std::vector<double> times = {10.0, 25.0, 10.2, 9.9, 10.1, 10.0, 9.8, 10.3};
  EXPECT_FALSE(enough_repetitions(adaptive, times));  // 8: [x(1), x(8)] still holds 25
  times.push_back(10.1);
  EXPECT_TRUE(enough_repetitions(adaptive, times));
  // Spread that never narrows stops at the maximum.
  std::vector<double> wild;
  for (int i = 0; i < 14; ++i) wild.push_back(i % 2 ? 5.0 : 20.0);
  EXPECT_FALSE(enough_repetitions(adaptive, wild));
  wild.push_back(5.0);
  EXPECT_TRUE(enough_repetitions(adaptive, wild));
}

TEST(RepetitionPolicy, TimingKeyTellsAdaptiveFromFixed) {
  TimingSpec fixed, adaptive;
  adaptive.repetitions = 3;
  adaptive.max_repetitions = 15;
  EXPECT_EQ(timing_key(fixed), "1,5");
  EXPECT_NE(timing_key(adaptive), timing_key(TimingSpec{1, 3}));
}

}  // namespace
}  // namespace aoeval
