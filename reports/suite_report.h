// The HTML report of `aoeval run`: one static, self-contained page (no scripts, no external URLs)
// over the rows of one run and the images the runner kept. Top: a summary table (suite, scenes,
// estimators, references, run id, git commit, machine, wall time). Per scene: a mosaic per featured
// row (reference | estimate | |error| | signed error, linked to the estimate and reference EXRs), a
// metrics table (matched and true AO) and a timing table. Per estimator: error against time over
// its sweep with the Pareto front marked, and the sweep's rows. Reads rows; runs nothing.
#pragma once

#include <string>
#include <vector>

#include "harness/results/suite_record.h"

namespace aoeval {

// Writes the error-against-time charts under <out_dir>/runs/<run_id>/plots/ and
// <out_dir>/index.html (atomically); returns the page's path.
std::string write_suite_report(const std::string& out_dir, const SuiteReport& report);

// The Pareto front of points (cost, error), both lower is better: true where no other point
// dominates it. j dominates i when error_j <= error_i and cost_j <= cost_i + t, with error_j <
// error_i or cost_j < cost_i - t, where t = max(cost_noise_i, cost_noise_j): costs closer than
// their measurement noise count as equal, so timing jitter alone never puts a less accurate point
// on the front. An empty `cost_noise` means zero noise (the textbook front). Points with a NaN
// coordinate are never on the front and dominate nothing. Equal points are all on it.
std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error,
                               const std::vector<double>& cost_noise = {});
// The timing noise of a row where fronts are decided: the interquartile range of its timed
// repetitions (issue 30: max - min let one slow repetition, 79 ms among 23-32 ms, make a 29 ms
// point "equal" to a 12 ms one and collapse the front); 0 when the row stored no repetitions.
double pareto_time_noise(const ResultRow& row);

}  // namespace aoeval
