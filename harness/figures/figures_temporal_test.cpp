// The checks of `rtao-convergence` (figures_temporal.h) on numbers on both sides of each rule.
#include "harness/figures/figures_temporal.h"

#include <gtest/gtest.h>

#include <cmath>

namespace aoeval::figures {
namespace {

TEST(RtaoConvergenceChecks, FirstFrameStayingBelow) {
  EXPECT_EQ(first_frame_staying_below({0.5, 0.2, 0.1, 0.1}, 0.2), 1);
  EXPECT_EQ(first_frame_staying_below({0.5, 0.1, 0.3, 0.1}, 0.2), 3);  // left again at frame 2
  EXPECT_EQ(first_frame_staying_below({0.5, 0.1, 0.3}, 0.2), -1);
  EXPECT_NEAR(steady_of({9.0, 9.0, 3.0, 4.0}), std::sqrt(12.5), 1e-12);  // frames 2, 3
}

ConvergenceNumbers passing() {
  ConvergenceNumbers n;
  n.rtao = {0.2, 0.1, 0.05, 0.04};
  n.rtao_no_atrous = {0.4, 0.2, 0.1, 0.08};
  n.raytraced[16] = {0.09, 0.09, 0.09, 0.09};
  n.rtao_steady = 0.045;
  n.no_atrous_steady = 0.09;
  n.settle_frames = 3;
  n.settle_sequence_frames = 48;
  return n;
}

TEST(RtaoConvergenceChecks, EachRuleOnBothSides) {
  for (const Check& c : rtao_convergence_checks(passing())) EXPECT_TRUE(c.passed) << c.rule;
  ConvergenceNumbers n = passing();
  n.rtao = {0.2, 0.1, 0.1, 0.1};  // never below 16 rays' 0.09
  EXPECT_FALSE(rtao_convergence_checks(n)[0].passed);
  n = passing();
  n.rtao_steady = 0.1;  // the a-trous passes made it worse
  EXPECT_FALSE(rtao_convergence_checks(n)[1].passed);
  n = passing();
  n.settle_frames = std::nan("");  // never settled
  EXPECT_FALSE(rtao_convergence_checks(n)[2].passed);
  n.settle_frames = kSettleFramesBound + 1;
  EXPECT_FALSE(rtao_convergence_checks(n)[2].passed);
  n.raytraced.clear();  // 16 rays not measured: the check cannot pass
  EXPECT_FALSE(rtao_convergence_checks(n)[0].passed);
}

TEST(GtaoTemporalChecks, EachRuleOnBothSides) {
  GtaoTemporalNumbers n;
  n.accumulated = {0.1, 0.05, 0.03, 0.021, 0.02, 0.02, 0.02, 0.02};
  n.six_slices = {0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02};
  n.accumulated_ms = 2.0;
  n.six_slices_ms = 8.0;
  for (const Check& c : gtao_temporal_checks(n)) EXPECT_TRUE(c.passed) << c.rule;
  GtaoTemporalNumbers m = n;
  m.accumulated = {0.1, 0.09, 0.08, 0.07, 0.06, 0.05, 0.04, 0.03};  // not close, not by frame 5
  EXPECT_FALSE(gtao_temporal_checks(m)[0].passed);
  EXPECT_FALSE(gtao_temporal_checks(m)[1].passed);
  m = n;
  m.accumulated_ms = 9.0;
  EXPECT_FALSE(gtao_temporal_checks(m)[2].passed);
}

TEST(TemporalEqualTimeChecks, EachRuleOnBothSides) {
  TemporalEqualTimeNumbers n;
  n.budget_ms = 10.0;
  n.contenders = {{"a", 0.02, 0.05, 6.0, 10.0}, {"b", 0.03, 0.01, std::nan(""), 12.0}};
  EXPECT_EQ(winner_by(n.contenders, &EqualTimeContender::settle), "a");  // NaN ranks last
  for (const Check& c : temporal_equal_time_checks(n)) EXPECT_TRUE(c.passed) << c.rule;
  TemporalEqualTimeNumbers m = n;
  m.contenders[1].ms = 16.0;  // over 1.5 x the budget
  EXPECT_FALSE(temporal_equal_time_checks(m)[0].passed);
  m = n;
  m.contenders[1].flicker = 0.09;  // a wins every question
  EXPECT_FALSE(temporal_equal_time_checks(m)[1].passed);
}

}  // namespace
}  // namespace aoeval::figures
