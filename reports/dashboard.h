// `aoeval dashboard` (CONTRACT §2, issue #7): the newest run in the SQLite history against a
// baseline run, row by row, under the noise-aware rules of reports/regression.h; an HTML page
// (failures first; per estimator and scene the new, baseline and difference images with a hover
// swap, and history charts of the tracked figures); a verdict the caller turns into the exit
// status (1 when something regressed).
//
// Rows are matched by run_name (estimator/params/scene/view/res). Rows left over on both sides
// are then paired within each (estimator, scene, view, resolution) in the order the runs stored
// them, when as many are left on each side (a suite runs its points in a fixed order): a run made
// with a changed parameter (`aoeval run --set E:K=V`) is still compared with its baseline, and
// the page names the parameters that changed. Rows still unpaired are new (no baseline) or
// missing (see Thresholds::missing_fails).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "harness/results/results_store.h"
#include "reports/regression.h"

namespace aoeval {

struct DashboardOptions {
  std::string database = "out/results.sqlite";
  // "" = the previous run of the same command as the new run, `--set` overrides aside
  std::string baseline_run;
  std::string new_run;  // "" = the newest run that has rows
  std::string out_dir = "out/dashboard";
  std::string config_path;   // "" = default_regression_config_path()
  size_t history_runs = 30;  // the newest runs shown in the history charts
  bool charts = true;        // false: no history charts (a python process each few charts)
};

// One row of the new run (or of the baseline, when the new run lacks it) and its verdict.
struct RowReport {
  std::string estimator, scene, view, resolution;
  std::string run_name;       // the new row's (the baseline's when missing)
  std::string params_change;  // "Ns: 16 -> 8" when paired by (estimator, scene, view, res)
  std::optional<ResultRow> before, after;  // either may be absent, not both
  std::vector<Check> checks;
  Verdict verdict = Verdict::not_compared;
  std::string note;  // "new row: no baseline", "skipped in both runs", ...
  // Images relative to the dashboard folder ("" when not available) and why not.
  std::string new_png, baseline_png, diff_png, image_note;
};

// History charts of one (estimator, scene), relative to the dashboard folder.
struct GroupCharts {
  std::string estimator, scene;
  std::vector<std::string> charts;
};

struct Dashboard {
  RunContext after_run;
  std::optional<RunContext> before_run;  // none: only one run of this command so far
  std::string config_source;
  std::vector<RowReport> rows;  // failures first, then warnings, improvements, the rest
  std::vector<GroupCharts> groups;
  int regressed = 0, warnings = 0, improved = 0, unchanged = 0, not_compared = 0;
  std::string page;  // <out>/index.html
};

// Reads the database, compares, writes <out>/index.html with its images and charts (atomically,
// file by file) and returns what it found. InputError (exit 2) when the database does not exist,
// holds no runs, or a named run is absent.
Dashboard build_dashboard(const DashboardOptions& options);

// One console line per regressed or warned row: "REGRESSED hbao-split scene bunny view main
// 320x240: rmse_excess 0.012 -> 0.020 (threshold 0.0006) ...".
std::vector<std::string> console_lines(const Dashboard& d);

// ---- parts (dashboard_images.cpp, dashboard_html.cpp)

// The estimate EXR of a row: absolute, or relative to its run's output folder; "" when the row
// kept none or the run recorded no output folder.
std::string estimate_path(const ResultRow& row, const RunContext& run);
// Writes new/baseline/difference PNGs for a compared row under <out>/images/ and fills the
// *_png fields; returns rms(new - baseline) over pixels covered in both when both EXRs were read.
std::optional<double> write_row_images(RowReport& row, const std::string& before_exr,
                                       const std::string& after_exr, const std::string& out_dir);
// Renders the history charts (rmse_excess and time_ms_median per (estimator, scene), one series
// per row) from `history` (runs oldest first, each with its rows) into <out>/charts/.
std::vector<GroupCharts> write_history_charts(
    const Dashboard& d, const std::vector<std::pair<RunContext, std::vector<ResultRow>>>& history,
    const std::string& out_dir);
// The page.
std::string dashboard_html(const Dashboard& d);

}  // namespace aoeval
