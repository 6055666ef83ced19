// Runs a suite (harness/sweep/suite.h); cmd/cmd_run.cpp then writes its report (reports/). Output
// folder:
//   index.html                  the report of this (the newest) run
//   results.csv, results.json   this run's rows (also appended to the SQLite history)
//   runs/<run_id>/estimates/    every row's estimate EXR (row.estimate_file, relative to the
//   folder) runs/<run_id>/mosaics/      reference | estimate | |error| | signed error of featured
//   rows runs/<run_id>/plots/        error against time per estimator runs/<run_id>/results.json  a
//   copy of this run's rows references/                 the reference EXRs the rows were scored
//   against gbuffers/index.html         the shared G-buffers of every scene view the suite renders
// Earlier runs' folders under runs/ are kept, so a dashboard can compare against a baseline.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/default_paths.h"
#include "harness/evaluation/evaluation.h"
#include "harness/results/run_recorder.h"
#include "harness/results/stage_times.h"
#include "harness/results/suite_record.h"

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
};

// What a run leaves for its report (cmd/cmd_run.cpp writes the page with reports/).
struct SuiteRun {
  std::string out_dir;
  SuiteReport report;                 // rows and the images kept beside them
  std::vector<GalleryEntry> gallery;  // the G-buffer EXRs written under <out>/gbuffers/
  size_t skipped = 0;                 // rows whose status is not "ok"
  StageTimes stages;                  // where the runner's time went (the page's is added later)
  // The references its sessions traced: passes over shared rays, images and rays (issue 42).
  EvaluationSession::ReferenceCounts references;
  std::string database;  // the SQLite store the rows went to
  // The run's bookkeeping, still holding the folder's lock while the caller writes the pages;
  // record_run_context() finishes it and lets the folder go.
  std::unique_ptr<RunRecorder> recorder;
};

// Runs every point, stores the rows (results.csv/json, SQLite) and keeps the images; writes no
// page.
SuiteRun run_suite(const SuiteRunOptions& options);

// Stores the run's finished context, with the "stages_ms" breakdown the caller measured once the
// page was written, in <out>/results.json, <out>/runs/<run_id>/results.json and the SQLite store,
// through the run's recorder, then releases the folder's lock.
void record_run_context(SuiteRun& run, const nlohmann::json& stages_ms);

}  // namespace aoeval
