// The subcommands of `aoeval` (CONTRACT §2). Each add_* function registers one subcommand with its
// options and the callback that runs it; main.cpp only assembles them and maps errors to exit
// codes.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>

#include "base/resolution.h"
#include "harness/results/stage_times.h"
#include "harness/sweep/suite_runner.h"

namespace aoeval {

void add_scenes_command(CLI::App& app);
void add_gbuffer_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_reference_command(CLI::App& app);
void add_estimators_command(CLI::App& app);
void add_estimate_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_bench_harness_command(CLI::App& bench);  // `bench harness`, inside add_bench_command
void add_figures_command(CLI::App& app);
void add_dashboard_command(CLI::App& app);
void add_merge_command(CLI::App& app);
void add_tune_command(CLI::App& app);

// `--frame K` of gbuffer and reference: digits only (a word or a sign is a parse error that says
// so; CLI11's NonNegativeNumber printed "not in range 0 to" the largest double, 310 digits).
// Whether the view has frame K is the scene's to say (sequence_frame).
inline CLI::Validator frame_number_check() {
  return CLI::Validator(
      [](std::string& text) {
        return !text.empty() && text.size() <= 9 &&
                       text.find_first_not_of("0123456789") == std::string::npos
                   ? std::string()
                   : "must be a frame number (a non-negative integer), got '" + text + "'";
      },
      "FRAME");
}

// `aoeval run`'s work: the suite, its pages, and the stage breakdown stored in the run's context.
// Also what `aoeval bench harness` times.
struct RunOutcome {
  std::string suite, page;  // the suite's name and the report page's path
  size_t rows = 0, skipped = 0;
  double wall_ms = 0.0;
  StageTimes stages;
  EvaluationSession::ReferenceCounts references;
};
RunOutcome run_suite_with_report(const SuiteRunOptions& options);

}  // namespace aoeval
