// One results row (CONTRACT §4 "Results"): one (estimator, parameters, scene, view, resolution)
// with its metrics against the matched reference and against true AO, its timings and its context.
// Every writer (console, CSV, JSON, SQLite, HTML) reads these rows and nothing else.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace aoeval {

inline constexpr int kResultsSchemaVersion = 1;

struct ResultRow {
  std::string run_id;    // one id per invocation of sweep/run/bench (all its rows share it)
  std::string run_name;  // stable: "raytraced/rays:16/scene:bunny/view:main/640x480"
  std::string estimator;
  nlohmann::json params = nlohmann::json::object();  // every effective parameter, defaults included
  std::string scene, view;
  int width = 0, height = 0;
  std::string definition;  // AoDefinition::to_json().dump() of the matched reference
  nlohmann::json reference =
      nlohmann::json::object();  // matched reference settings (spp, sampler, seed)
  nlohmann::json metrics = nlohmann::json::object();  // metric_keys() against the matched reference
  nlohmann::json true_metrics = nlohmann::json::object();  // the same keys against true AO
  double time_ms_median = 0.0, time_ms_min = 0.0, time_ms_max = 0.0;
  int repetitions = 0;
  // Every timed repetition in ms, in order (what the dashboard's rank test compares); the
  // "time_ms_samples" column holds them as a JSON array.
  std::vector<double> time_ms_samples;
  // Sets the time columns from every timed repetition (median, min, max, count, samples).
  void set_times(const std::vector<double>& samples_ms);
  std::map<std::string, double> pass_ms;  // per-pass GPU/CPU times, column names end in "_ms"
  double precompute_ms = 0.0;
  std::string backend;  // cpu, embree, vulkan
  std::string machine, device, git_commit, aoeval_version;
  // The estimator's code (estimator_code_version, registry.h): "built-in:<12 hex>", "glsl:<12 hex>"
  // or "process:<12 hex>"; "" in files written before the column existed.
  std::string estimator_version;
  std::string timestamp;      // ISO 8601 UTC, when the row was measured
  std::string estimate_file;  // relative path of the estimate EXR, "" if not kept
  std::string status = "ok";  // "ok", or "skipped: <reason>" (e.g. no Vulkan device)
  // What the time columns measure: "wall" (the harness's clock around one frame),
  // "gpu-timestamps", "plugin-frames" (a process plug-in's own frame_ms), "process-wall" (a
  // process plug-in's whole process: start-up and file I/O included), "frame-wall" (a
  // "protocol": "frames" plug-in's request-to-answer round trip). CONTRACT §7, §10.
  std::string timing_source;
};

// The row as one flat JSON object whose keys are exactly the CSV/SQLite column names: fixed
// columns, then one column per parameter (named after it), metrics, "true_" metrics, timings.
nlohmann::json flatten(const ResultRow& row);
// The one way a row read from disk becomes a ResultRow: it is checked (run_name and estimator
// present and non-empty, every fixed column of its type, metrics numbers or null), and a row that
// fails is an InputError "<where>.<column>: <problem>" (`where` names the file and the row, e.g.
// "out/x/results.json: rows[3]").
ResultRow unflatten(const nlohmann::json& flat, const std::string& where = "results row");

// The fixed columns in order, for writers that need a stable header. Parameter columns come
// between the identifying columns and the metrics; pass-time columns at the end.
std::vector<std::string> identifying_columns();  // run_id, run_name, estimator, scene, view, ...
// The sequence keys of CONTRACT §10 (scoring/temporal.h computes them), in column order; blank
// for still views.
const std::vector<std::string>& sequence_metric_names();
std::vector<std::string> measured_columns();  // metrics, true_ metrics, timings, context
// identifying_columns() and measured_columns() as one set: every column that is not a parameter's
// or a pass's.
const std::set<std::string>& fixed_columns();

// A file name for a run name: its readable part, then 8 hex digits of the name's FNV-1a hash, so
// that names which read alike once sanitised (views "a<b" and "a>b") get files of their own:
// "raytraced/rays:16/scene:bunny" -> "raytraced__rays-16__scene-bunny_<8 hex>".
std::string file_stem_for(const std::string& run_name);
// InputError naming `where` and both points when two different run names would still share a
// file stem (a hash collision): one file per point, never one overwriting another.
void check_file_stems(const std::vector<std::string>& run_names, const std::string& where);

}  // namespace aoeval
