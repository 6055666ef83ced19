// The HTML report of `aoeval run`: one static, self-contained page (no scripts, no external URLs)
// over the rows of one run and the images the runner kept. Top: a summary table (suite, scenes,
// estimators, references, run id, git commit, machine, wall time). Per scene: a mosaic per featured
// row (reference | estimate | |error| | signed error, linked to the estimate and reference EXRs), a
// metrics table (matched and true AO) and a timing table. Per estimator: error against time over
// its sweep with the Pareto front marked, and the sweep's rows. Reads rows; runs nothing.
#pragma once

#include <string>
#include <vector>

#include "harness/results/pareto.h"  // the front the charts and mosaics mark
#include "harness/results/suite_record.h"

namespace aoeval {

// Writes the error-against-time charts under <out_dir>/runs/<run_id>/plots/ and
// <out_dir>/index.html (atomically); returns the page's path.
std::string write_suite_report(const std::string& out_dir, const SuiteReport& report);

}  // namespace aoeval
