// Runs a sweep: expands the spec, takes this shard, skips rows already in the output folder when
// resuming, evaluates the rest one by one and stores each row the moment it exists (results.csv and
// results.json rewritten atomically, one SQLite transaction). SIGINT stops it between two rows, so
// an interrupted sweep resumes without losing or duplicating a row.
#pragma once

#include <string>

#include "base/default_paths.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {

struct SweepOptions {
  std::string spec_path;
  std::string out_dir;  // default out/<spec name>
  bool resume = false;
  std::string shard;  // "I/N", "auto" or ""
  std::string
      shard_plan;  // with shard: the plan's shard instead of every N-th point (shard_plan.h)
  std::string database = kDefaultDatabase;
  bool keep_estimates = true;                  // write each estimate's EXR under <out>/estimates/
  size_t max_points = kDefaultMaxSweepPoints;  // --max-points
  // Writes the folder's pages from the store when the sweep was not interrupted, while it still
  // holds the folder (cmd/ hands in reports/run_pages.h; its path goes to run_sweep's `page`).
  PageWriter pages;
};

// Returns the exit status: 0 done, 130 interrupted. Besides the rows, writes the folder's
// suite_record.json (the references each row was scored against, under <out>/references/), from
// which `aoeval sweep` and `aoeval merge` write its page; `out_dir` receives the output folder.
int run_sweep(const SweepOptions& options, std::string* out_dir = nullptr,
              std::string* page = nullptr);

}  // namespace aoeval
