// The one Pareto rule of error against time: the report's charts and mosaics (reports/) and
// tune.png (harness/tune/) both mark fronts with it, so a page and a tune cannot disagree about
// which points are on the front. In the results room, the leaf both may use.
#pragma once

#include <vector>

#include "harness/results/result_row.h"

namespace aoeval {

// The Pareto front of points (cost, error), both lower is better: true where no other point
// dominates it. j dominates i when error_j <= error_i and cost_j <= cost_i + t, with error_j <
// error_i or cost_j < cost_i - t, where t = max(cost_noise_i, cost_noise_j): costs closer than
// their measurement noise count as equal, so timing jitter alone never puts a less accurate point
// on the front. An empty `cost_noise` means zero noise (the textbook front). Points with a NaN
// coordinate are never on the front and dominate nothing. Equal points are all on it.
// std::invalid_argument when the lengths differ.
std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error,
                               const std::vector<double>& cost_noise = {});
// The timing noise of a row where fronts are decided: the interquartile range of its timed
// repetitions (issue 30: max - min let one slow repetition, 79 ms among 23-32 ms, make a 29 ms
// point "equal" to a 12 ms one and collapse the front); 0 when the row stored no repetitions.
double pareto_time_noise(const ResultRow& row);

}  // namespace aoeval
