// `aoeval tune SPEC.json [--out DIR] [--db FILE]` (CONTRACT §8): searches an estimator's
// parameters for the least mean error over the spec's views under a frame-time budget
// (tune_search.h: the optimiser; tune_budget.h: how the budget is judged).
//
// Every evaluation is a normal results row (one per view), stored the moment it exists through the
// sweep's machinery: results.csv and results.json rewritten atomically, the SQLite history, one
// run id. Re-running the same command on the same folder continues an interrupted tune: the search
// is deterministic, so it proposes the same points again, and each one whose rows are already in
// the folder (or committed to SQLite) is read back, not recomputed. A folder holds one tune: a
// different spec in the same --out is an error.
//
// Output folder: results.csv, results.json, tune.json (best parameters, objective, time,
// evaluations used, the optimiser and its settings, feasible; every trial), tune.png (objective by
// evaluation, and error against time with the Pareto front and the budget).
#pragma once

#include <string>

#include "base/default_paths.h"
#include "harness/tune/tune_spec.h"

namespace aoeval {

struct TuneOptions {
  std::string spec_path;
  std::string out_dir;  // default out/<spec name>
  std::string database = kDefaultDatabase;
  bool plot = true;        // tune.png (tests that do not need it save matplotlib's start-up)
  EstimatorLookup lookup;  // default: the registry
};

// Returns the exit status: 0 done (also when no point met the budget: tune.json says
// "feasible": false and stderr says "no feasible point"), 130 interrupted (SIGINT).
int run_tune(const TuneOptions& options);

}  // namespace aoeval
