// `aoeval merge DIR... --out DIR [--db FILE]` (CONTRACT §9): the output folders of shards (of one
// `--slurm` submission, of `--shard I/N` runs under GNU parallel, or of separate machines) become
// one result set: every row exactly once, one results.csv/results.json, the rows appended to the
// SQLite history as one run, and, for suite runs, the report a single-machine run writes (through
// the PageWriter cmd/cmd_merge.cpp hands in; this room never links reports/).
#pragma once

#include <string>
#include <vector>

#include "base/default_paths.h"
#include "harness/results/results_store.h"
#include "harness/results/suite_record_io.h"

namespace aoeval {

struct MergeOptions {
  std::vector<std::string> dirs;
  std::string out;
  std::string database = kDefaultDatabase;
  // Optional: the shard plan of a --slurm submission (sweep/shard_plan.h). With it, every planned
  // point must be present (a failed shard is named, and nothing is merged), and rows follow the
  // plan's order, which is the single-machine order.
  std::string plan;
  // For suite runs (every folder holds suite_record.json): writes the merged folder's pages from
  // the store while the merge still holds the folder (cmd/ hands in reports/run_pages.h).
  PageWriter pages;
};

// Per-shard wall times that the shards' job scripts wrote (<dir>/shard.json), against the plan.
struct ShardTiming {
  std::string dir;
  int index = -1;
  double wall_s = 0.0;
  double planned_ms = 0.0;
  std::string node;
};

struct MergeResult {
  std::string out;
  RunContext context;
  std::vector<ResultRow> rows;
  size_t duplicates = 0;  // rows found in two folders with the same values, kept once
  std::string page;       // the report's path; "" when the folders are not all suite runs or sweeps
  std::vector<ShardTiming> timings;
  double measured_ratio = 0.0;  // slowest / mean measured shard wall time (0: no shard.json)
  double planned_ratio = 0.0;   // slowest / mean planned shard cost (0: no plan)
};

// InputError (exit 2) for a folder without results, and for a row present in two folders with
// different values (naming the row and both folders); std::runtime_error (exit 1) when the plan's
// points are not all present (naming the incomplete shards and how many points each lacks).
MergeResult merge_results(const MergeOptions& options);

// The row's values that must agree between two copies of one point: parameters, definition,
// reference, status and every metric. Timings, machine and run id may differ (the same point
// measured twice); "" when they agree, else the first differing field.
std::string row_conflict(const ResultRow& a, const ResultRow& b);

}  // namespace aoeval
