// How `aoeval tune` decides whether a point meets its time budget (CONTRACT §8: the mean over the
// spec's views of the median frame time). Frame times on a shared machine are noisy, so a point is
// judged from its repetitions, not from one number:
//
//   clearly feasible    mean over views of the slowest repetition <= budget
//   clearly infeasible  mean over views of the fastest repetition  >  budget
//   borderline          otherwise: the budget lies inside the repetitions' spread. The point is
//                       re-timed once (2 x repetitions more frames per view, pooled with the first
//                       ones, all kept in its rows) and then judged by the pooled mean median.
//
// The spread (max - min) holds the true median with probability 1 - 2^(1-n) (75 % at 3, 94 % at 5)
// for any distribution, so a point is only re-timed where the first measurement cannot tell.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

enum class TimeVerdict { feasible, infeasible, borderline };
const char* time_verdict_name(TimeVerdict v);

struct TimeJudgement {
  double mean_median = 0.0, mean_min = 0.0, mean_max = 0.0;  // over views, ms
  TimeVerdict verdict = TimeVerdict::feasible;
};

// `samples` holds each view's repetitions (ms). `retimed`: the samples are already pooled after a
// re-time, so the verdict is final (feasible iff mean median <= budget). budget_ms <= 0: feasible.
TimeJudgement judge_time(const std::vector<std::vector<double>>& samples, double budget_ms,
                         bool retimed);

// The median of a non-empty list (the mean of the two middle values for an even count).
double median_of(std::vector<double> values);

}  // namespace aoeval
