// The one Pareto rule (pareto.h) that the report's charts and mosaics and tune.png share.
#include "harness/results/pareto.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace aoeval {
namespace {

TEST(ParetoFront, KeepsPointsNoOtherBeatsOnBothAxes) {
  //   error
  //   0.30 a
  //   0.20    b     d (dominated by b: slower, same error)
  //   0.10          c
  //   0.15             e (dominated by c)
  //        1  2     4  8   cost
  const std::vector<double> cost = {1, 2, 4, 4, 8}, error = {0.3, 0.2, 0.1, 0.2, 0.15};
  EXPECT_EQ(pareto_front(cost, error), (std::vector<bool>{true, true, true, false, false}));
}

TEST(ParetoFront, TiesAndEdgeCases) {
  EXPECT_TRUE(pareto_front({}, {}).empty());
  EXPECT_EQ(pareto_front({5}, {0.5}), std::vector<bool>{true});
  // Identical points do not dominate each other.
  EXPECT_EQ(pareto_front({1, 1}, {0.2, 0.2}), (std::vector<bool>{true, true}));
  // Same cost, one more accurate: only that one.
  EXPECT_EQ(pareto_front({1, 1}, {0.2, 0.1}), (std::vector<bool>{false, true}));
  // A point better on both axes dominates everything.
  EXPECT_EQ(pareto_front({3, 1, 2}, {0.3, 0.05, 0.2}), (std::vector<bool>{false, true, false}));
  // NaN never joins the front and never dominates.
  const double nan = std::nan("");
  EXPECT_EQ(pareto_front({1, nan, 2}, {0.2, 0.0, 0.1}), (std::vector<bool>{true, false, true}));
  EXPECT_THROW(pareto_front({1, 2}, {0.1}), std::invalid_argument);
}

TEST(ParetoFront, OneSlowRepetitionCannotCollapseTheFront) {
  // Issue 30: a 12 ms point and a more accurate 29 ms point whose repetitions hold one slow one
  // (79 ms among 23-32 ms). With max - min as the noise (56 ms) the 29 ms point "dominated" the
  // 12 ms one; the interquartile range (5 ms) keeps both on the front.
  ResultRow fast, slow;
  fast.set_times({11.5, 12.0, 12.0, 12.5, 13.0});
  slow.set_times({23.0, 27.0, 29.0, 32.0, 79.0});
  ASSERT_EQ(slow.time_ms_median, 29.0);
  const std::vector<double> cost = {fast.time_ms_median, slow.time_ms_median}, error = {0.2, 0.1};
  EXPECT_EQ(
      pareto_front(cost, error,
                   {fast.time_ms_max - fast.time_ms_min, slow.time_ms_max - slow.time_ms_min}),
      (std::vector<bool>{false, true}));  // the old rule's collapse, kept as the witness
  EXPECT_DOUBLE_EQ(pareto_time_noise(slow), 5.0);
  EXPECT_DOUBLE_EQ(pareto_time_noise(fast), 0.5);
  EXPECT_EQ(pareto_front(cost, error, {pareto_time_noise(fast), pareto_time_noise(slow)}),
            (std::vector<bool>{true, true}));
  EXPECT_EQ(pareto_time_noise(ResultRow{}), 0.0);  // no repetitions stored
}

TEST(ParetoFront, CostsWithinTheirNoiseCountAsEqual) {
  // Three settings that cost the same up to timing jitter (spread 0.05 ms each): only the most
  // accurate is on the front, although the least accurate happens to be the fastest.
  const std::vector<double> cost = {0.150, 0.152, 0.170}, error = {0.5, 0.2, 0.3};
  EXPECT_EQ(pareto_front(cost, error), (std::vector<bool>{true, true, false}));
  EXPECT_EQ(pareto_front(cost, error, {0.05, 0.05, 0.05}), (std::vector<bool>{false, true, false}));
  // A real speed-up (beyond the noise) keeps the faster, less accurate point on the front.
  EXPECT_EQ(pareto_front({1.0, 4.0}, {0.3, 0.1}, {0.5, 0.5}), (std::vector<bool>{true, true}));
  // The larger of the two noises applies.
  EXPECT_EQ(pareto_front({1.0, 1.4}, {0.3, 0.1}, {0.0, 0.5}), (std::vector<bool>{false, true}));
  // Equal errors: the clearly cheaper one wins; within the noise both stay.
  EXPECT_EQ(pareto_front({1.0, 2.0}, {0.1, 0.1}, {0.1, 0.1}), (std::vector<bool>{true, false}));
  EXPECT_EQ(pareto_front({1.0, 1.05}, {0.1, 0.1}, {0.1, 0.1}), (std::vector<bool>{true, true}));
  EXPECT_THROW(pareto_front({1, 2}, {0.1, 0.2}, {0.1}), std::invalid_argument);
}

TEST(ParetoFront, ATunesTrialsAreJudgedAsTheReportJudgesRows) {
  // tune.png's front (harness/tune/tune_plot.cpp) and the report's come from this one function:
  // trials (objective 0.1 at 10 ms, 0.2 at 5 ms, 0.2 at 10 ms, 0.05 at 20 ms) as the tune search
  // once judged them with a rule of its own.
  EXPECT_EQ(pareto_front({10, 5, 10, 20}, {0.1, 0.2, 0.2, 0.05}),
            (std::vector<bool>{true, true, false, true}));
}

}  // namespace
}  // namespace aoeval
