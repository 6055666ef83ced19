// Runs a suite (harness/sweep/suite.h) and, through the PageWriter cmd/cmd_run.cpp hands it, writes
// its pages from the store. Output folder:
//   index.html                  the report of this (the newest) run
//   results.csv, results.json   this run's rows (also appended to the SQLite history)
//   runs/<run_id>/estimates/    every row's estimate EXR (row.estimate_file, relative to the
//   folder) runs/<run_id>/mosaics/      reference | estimate | |error| | signed error of featured
//   rows runs/<run_id>/plots/        error against time per estimator runs/<run_id>/results.json  a
//   copy of this run's rows references/                 the reference EXRs the rows were scored
//   against gbuffers/index.html         the shared G-buffers of every scene view the suite renders
// Earlier runs' folders under runs/ are kept, so a dashboard can compare against a baseline.
#pragma once

#include <string>
#include <vector>

#include "base/default_paths.h"
#include "harness/evaluation/evaluation.h"
#include "harness/results/stage_times.h"
#include "harness/results/suite_record_io.h"

namespace aoeval {

struct SuiteRunOptions {
  std::string suite = "default";  // a shipped suite's name or a suite file's path
  std::string out_dir;            // default out/<suite name>
  std::string database = kDefaultDatabase;
  std::vector<std::string> sets;  // "ESTIMATOR:KEY=VALUE"
  std::string shard;              // "I/N", "auto" or "": this shard's points only (CONTRACT §9)
  std::string shard_plan;         // with shard: the cost-balanced plan (shard_plan.h)
  // Start the report's plot workers (drawing/plot_workers.h) at the start of the run, stopped
  // while frames are timed: set by `aoeval run`, which draws the report's charts at the end.
  bool prestart_plot_workers = false;
  // The kept references and sequence frames as the cache's float32s, bit for bit (`aoeval run
  // --viewer-exact`); false: at float16 precision, about 1.6x smaller (kept_references.h).
  bool exact_kept_files = false;
  // Writes the folder's pages (cmd/ hands in reports/run_pages.h); none when empty.
  PageWriter pages;
};

// What a run did (the folder and the store hold what it measured).
struct SuiteRun {
  std::string suite, out_dir;
  std::string page;    // the report's path ("" without SuiteRunOptions::pages)
  size_t rows = 0;     // rows recorded
  size_t skipped = 0;  // rows whose status is not "ok"
  StageTimes stages;   // where the run's time went, the pages' included
  double wall_ms = 0.0;
  // The references its sessions traced: passes over shared rays, images and rays (issue 42).
  EvaluationSession::ReferenceCounts references;
};

// Runs every point, stores the rows (results.csv/json, SQLite) and keeps the images and the
// folder's record (suite_record.json); then, still holding the folder's lock, writes the pages
// with `options.pages` (from the store, not from memory) and stores the run's finished context,
// with its "stages_ms" breakdown, in <out>/results.json, <out>/runs/<run_id>/results.json and the
// SQLite store.
SuiteRun run_suite(const SuiteRunOptions& options);

}  // namespace aoeval
