#include "harness/tune/tune_budget.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "base/summary.h"

namespace aoeval {

const char* time_verdict_name(TimeVerdict v) {
  switch (v) {
    case TimeVerdict::feasible:
      return "feasible";
    case TimeVerdict::infeasible:
      return "infeasible";
    case TimeVerdict::borderline:
      return "borderline";
  }
  return "?";
}

double median_of(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("median of no values");
  return median(std::move(v));
}

TimeJudgement judge_time(const std::vector<std::vector<double>>& samples, double budget_ms,
                         bool retimed) {
  if (samples.empty()) throw std::invalid_argument("judge_time: no views");
  TimeJudgement j;
  for (const auto& s : samples) {
    j.mean_median += median_of(s);
    j.mean_min += *std::min_element(s.begin(), s.end());
    j.mean_max += *std::max_element(s.begin(), s.end());
  }
  const double n = static_cast<double>(samples.size());
  j.mean_median /= n;
  j.mean_min /= n;
  j.mean_max /= n;
  if (budget_ms <= 0.0) {
    j.verdict = TimeVerdict::feasible;
  } else if (retimed) {
    j.verdict = j.mean_median <= budget_ms ? TimeVerdict::feasible : TimeVerdict::infeasible;
  } else if (j.mean_max <= budget_ms) {
    j.verdict = TimeVerdict::feasible;
  } else if (j.mean_min > budget_ms) {
    j.verdict = TimeVerdict::infeasible;
  } else {
    j.verdict = TimeVerdict::borderline;
  }
  return j;
}

}  // namespace aoeval
