// `aoeval dashboard` (CONTRACT §2, issue #7): the newest run in the SQLite history against a
// baseline run, row by row, under the noise-aware rules of reports/regression.h; an HTML page
// (failures first; per estimator and scene the new, baseline and difference images with a hover
// swap, and history charts of the tracked figures); a verdict the caller turns into the exit
// status (1 when something regressed).
//
// Rows are matched by run_name (estimator/params/scene/view/res). Rows left over on both sides
// are then paired within each (estimator, scene, view, resolution) in the order the runs stored
// them, when as many are left on each side (a suite runs its points in a fixed order): a run made
// with a changed parameter (`aoeval run --set E:K=V`) is still compared with its baseline. A run
// name holds only the parameters the sweep or suite set explicitly, so a changed default (a
// plug-in manifest's) keeps the name and the pair. Every pair names the parameters whose
// effective values differ, defaults included ("alpha 0.1 -> 0.41"), and the code that changed
// (aoeval version, git commit). Rows still unpaired are new (no baseline) or missing (see
// Thresholds::missing_fails).
//
// Every key the metric table flags for the dashboard is judged (regression.h), so a row can have
// a key that regressed and another that improved: it counts in both (Dashboard::both) and its
// REGRESSED line says "also IMPROVED: ...".
//
// Changes (CONTRACT §12, image_change.h): every compared row's two estimate images give its
// mean_shift and changed_pixels; a row beyond change_mean_shift (and its noise) is CHANGED, a
// verdict apart from regressed/improved: it fails the run only under "change_action": "fail".
// History (--history N, dashboard_history.cpp): the last N runs of the suite or sweep, each row's
// rmse_excess, every other flagged key it carries (the sequence keys), mean AO and median time as
// series, and their steps (change_points.h).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base/default_paths.h"
#include "harness/results/results_store.h"
#include "reports/frame_change.h"
#include "reports/image_change.h"
#include "reports/regression.h"

namespace aoeval {

class RegressionConfig;

struct DashboardOptions {
  std::string database = kDefaultDatabase;
  // "" = the previous run of the same command as the new run, `--set` overrides aside
  std::string baseline_run;
  std::string new_run;  // "" = the newest run that has rows
  std::string out_dir = "out/dashboard";
  std::string config_path;   // "" = default_regression_config_path()
  size_t history_runs = 30;  // the newest runs shown in the history charts
  bool charts = true;        // false: no history charts (a python process each few charts)
  size_t history_steps = 0;  // --history N: find steps over the last N runs (0: not asked)
  // Each known estimator's parameters at their defaults (the registry's; the caller fills it), so
  // console lines name the parameters that differ from them first. Absent estimators: the
  // parameters named in the row's run name (those set explicitly) come first.
  std::map<std::string, nlohmann::json> estimator_defaults;
};

// One row of the new run (or of the baseline, when the new run lacks it) and its verdict.
struct RowReport {
  std::string estimator, scene, view, resolution;
  std::string run_name;       // the new row's (the baseline's when missing)
  std::string params_change;  // "Ns 16 -> 8, alpha 0.1 -> 0.41": effective values that differ
  // "glsl-plugin:my-ao 3f2a91c -> 8b0d4e2, aoeval 0.1.0 -> 0.2.0, commit 0123abcd4567 -> 89ab...":
  // the estimator's code version (estimator_version), aoeval's version, the commit; "" same
  std::string code_change;
  std::optional<ResultRow> before, after;  // either may be absent, not both
  std::vector<Check> checks;
  Verdict verdict = Verdict::not_compared;
  std::string note;  // "new row: no baseline", "skipped in both runs", ...
  // Images relative to the dashboard folder ("" when not available) and why not.
  std::string new_png, baseline_png, diff_png, image_note;
  // The estimate's change against the baseline's (both images read), and whether it counts.
  std::optional<ImageChange> change;
  double change_limit = 0.0;  // change_threshold(): what |mean_shift| had to exceed
  bool changed = false, change_fails = false;
  std::string params_text;  // "rays=1,seed=7,...": differing from defaults first
  // A sequence point's frames against the baseline's (frame_change.h), both read from the
  // history's frames table; none for a still view or a history without frames.
  std::optional<FrameChange> frames;
  std::vector<FrameRow> before_frames, after_frames;  // as read, for the per-frame chart
};

// One step of one series over the history (CONTRACT §12 STEP lines).
struct SeriesStep {
  std::string series;  // the row's run name
  std::string estimator, scene;
  std::string figure;  // "rmse_excess" (or another flagged key), "mean", "time_ms_median"
  RunContext run;      // the first run of the new level
  double before = 0.0, after = 0.0, p = 0.0;
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
  // Rows by verdict; a row with a regressed key and an improved one counts in regressed and in
  // improved, and in both.
  int regressed = 0, warnings = 0, improved = 0, unchanged = 0, not_compared = 0, both = 0;
  // Per judged key (Check::figure): rows where it regressed and where it improved.
  std::map<std::string, std::pair<int, int>> by_key;
  int changed = 0, changes_failing = 0;  // CHANGED rows; those whose change_action is "fail"
  bool history_searched = false;         // --history was given
  size_t history_size = 0;               // runs in the history searched
  std::vector<SeriesStep> steps;         // in series order, then run order
  // Mean AO of each history row's estimate, "<run_id>|<run_name>" (read by find_steps, drawn by
  // the charts).
  std::map<std::string, double> mean_ao;
  std::string page;  // <out>/index.html
};

// Reads the database, compares, writes <out>/index.html with its images and charts (atomically,
// file by file) and returns what it found. InputError (exit 2) when the database does not exist,
// holds no runs, or a named run is absent.
Dashboard build_dashboard(const DashboardOptions& options);

// The console lines (CONTRACT §12), one per regressed, warned or improved row ("REGRESSED
// hbao-split R=0.4,Nd=8,... scene bunny view main 320x240: rmse_excess 0.012 -> 0.020 (threshold
// 0.0006)"), per changed row ("CHANGED vo-loos R=0.5,... scene bunny view main 160x120: darker by
// 0.050 mean AO on 97 % of pixels") and per step ("STEP <run name> at run <run_id> (<commit>):
// rmse_excess 0.0210 -> 0.0341"), and per sequence row whose frames changed ("FRAMES raytraced
// rays=4,... scene dragon view walk 160x120: rmse_excess changed on frames 12-20 (...)").
std::vector<std::string> console_lines(const Dashboard& d);
// "rmse_excess changed on frames 12-20 (9 of 48 frames; most at frame 15: 0.0123 -> 0.0456)", or
// "rmse_excess unchanged on all 48 frames".
std::string frames_phrase(const FrameChange& f);
// True when the dashboard's exit status is 1: a regression, or a change under change_action fail.
bool dashboard_fails(const Dashboard& d);
// "Ns 16 -> 8, alpha 0.1 -> 0.41": the keys whose values differ ("(none)" where one side lacks
// it), "derived" left out; "" when none differ.
std::string params_change(const nlohmann::json& before, const nlohmann::json& after);
// "k=v,k=v": `params` ("derived" left out), those differing from `defaults` (or, without defaults,
// those named in `run_name`) first, each group in key order; "-" when there are none.
std::string params_text(const nlohmann::json& params, const std::string& run_name,
                        const nlohmann::json* defaults);

// ---- parts (dashboard_images.cpp, dashboard_html.cpp)

// The estimate EXR of a row: absolute, or relative to its run's output folder; "" when the row
// kept none or the run recorded no output folder.
std::string estimate_path(const ResultRow& row, const RunContext& run);
// Writes new/baseline/difference PNGs for a compared row under <out>/images/ and fills the
// *_png fields; returns rms(new - baseline) over pixels covered in both.
std::optional<double> write_row_images(RowReport& row, const AoPlanes& before,
                                       const AoPlanes& after, const std::string& out_dir);
// Finds the steps of every tracked series over `history` (runs oldest first, each with its rows;
// dashboard_history.cpp) into d.steps.
void find_steps(Dashboard& d,
                const std::vector<std::pair<RunContext, std::vector<ResultRow>>>& history,
                const RegressionConfig& config);
// Renders the history charts (rmse_excess and time_ms_median per (estimator, scene), and mean AO
// when steps were searched; one series per row, steps marked) from `history` into <out>/charts/.
std::vector<GroupCharts> write_history_charts(
    const Dashboard& d, const std::vector<std::pair<RunContext, std::vector<ResultRow>>>& history,
    const std::string& out_dir);
// The page; it loads dashboard.css and dashboard.js beside it (reports/pages/, page_assets.h).
std::string dashboard_html(const Dashboard& d);

}  // namespace aoeval
