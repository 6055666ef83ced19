#include "harness/tune/tune_runner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "base/errors.h"
#include "base/json_reader.h"
#include "harness/evaluation/progress.h"
#include "harness/results/pareto.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "harness/tune/tune_budget.h"
#include "harness/tune/tune_plot.h"
#include "harness/tune/tune_search.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// Pools a re-timed row's repetitions with the first measurement's: the row keeps every sample.
ResultRow pooled(const ResultRow& first, ResultRow again) {
  std::vector<double> all = first.time_ms_samples;
  all.insert(all.end(), again.time_ms_samples.begin(), again.time_ms_samples.end());
  again.set_times(all);
  return again;
}

// How many time samples a row's first measurement holds: the spec's repetitions for a still view,
// the frame count for a sequence (each frame is timed once, CONTRACT §10). A row with more has been
// re-timed.
int first_samples(const ResultRow& row, int repetitions) {
  const auto it = row.metrics.find("seq_frames");
  return it != row.metrics.end() && it->is_number_integer() ? it->get<int>() : repetitions;
}

// A row's value of the objective `key`. psnr is null where the images are identical: as good as
// psnr gets. A sequence score is null where it has no value (settle_frames when no trajectory
// qualifies, lag_rmse_excess when the truth moved nowhere in view, disocclusion_rmse_excess when
// nothing was disoccluded, temporal_* of a single frame): the objective is undefined for that row
// and the tune stops with the reason.
double objective_of(const ResultRow& r, const nlohmann::json& m, const std::string& key,
                    const std::string& objective, const std::string& where) {
  const auto it = m.find(key);
  if (it == m.end())
    throw InputError(where + ": tune.objective: " + objective + " is absent from " + r.run_name +
                     (key.rfind("bent_", 0) == 0 ? " (the estimator gives no bent normal)" : ""));
  if (!it->is_null()) return it->get<double>();
  if (key == "psnr") return 999.0;
  const std::string why =
      key == "settle_frames"
          ? "no trajectory stayed in view for 13 frames after a disocclusion with its truth "
            "holding still; tune it on a longer sequence where something moves"
      : key == "disocclusion_rmse_excess"
          ? "no pixel was disoccluded in that sequence; tune it on a sequence where something "
            "moves"
      : key == "lag_rmse_excess"
          ? "the truth moved nowhere under a surface in view; tune it on a sequence with a "
            "moving object"
          : "the sequence has a single frame";
  throw InputError(where + ": tune.objective: " + objective + " has no value for " + r.run_name +
                   " (" + why + ")");
}

// What tune.json says of each trial, beyond the search's Outcome.
struct TrialRecord {
  double objective = 0.0;  // as the metric reads (not negated)
  TimeJudgement time;
  bool retimed = false;
  std::vector<std::string> run_names;
  std::string status = "ok";
};

nlohmann::json trial_json(const TuneSpec& spec, const Trial& t, const TrialRecord& r, size_t i) {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& p : spec.params) params[p.spec->name] = t.overrides[p.spec->name];
  nlohmann::json j = {
      {"index", i}, {"params", params}, {"status", r.status}, {"run_names", r.run_names}};
  if (r.status == "ok") {
    j["objective"] = r.objective;
    j["time_ms"] = r.time.mean_median;
    j["time_ms_min"] = r.time.mean_min;
    j["time_ms_max"] = r.time.mean_max;
    j["feasible"] = t.outcome.feasible;
    j["retimed"] = r.retimed;
  }
  return j;
}

nlohmann::json point_json(const TuneSpec& spec, const Trial& t, const TrialRecord& r, size_t i) {
  nlohmann::json j = trial_json(spec, t, r, i);
  j["overrides"] = t.overrides;  // fixed values included: what `aoeval estimate --set` takes
  j["effective_params"] =
      resolve_params(spec.estimator->name, spec.estimator->params, t.overrides, spec.name).json();
  return j;
}

}  // namespace

int run_tune(const TuneOptions& o) {
  const TuneSpec spec = load_tune_spec(o.spec_path, o.lookup);
  const std::string out = o.out_dir.empty() ? "out/" + spec.name : o.out_dir;
  // The recorder's order (run_recorder.h): database, folder lock, leftovers of killed writes,
  // results.json with the run id before any row reaches the database, then each row to SQLite
  // first and to the files after.
  RunRecorder recorder(out, o.database, "tune " + spec.name, FolderAccess::exclusive);
  const fs::path tune_json = fs::path(out) / "tune.json";
  if (fs::exists(tune_json)) {
    const nlohmann::json previous = parse_json_file(tune_json.string());
    if (!previous.is_object() || previous.value("spec", nlohmann::json()) != spec.document)
      throw InputError(out + ": holds another tune (its tune.json has a different spec than " +
                       o.spec_path + "); choose another --out");
  } else if (fs::exists(fs::path(out) / "results.json")) {
    throw InputError(out + ": already holds results that are not a tune's; choose another --out");
  }
  recorder.context().output_dir = fs::absolute(out).lexically_normal().string();
  // A tune always continues the one in its folder: one tune is one run however often it was
  // interrupted.
  recorder.resume();
  recorder.write_files();
  recorder.register_run();
  const RunContext& context = recorder.context();
  write_text(tune_json.string(), nlohmann::json{{"name", spec.name},
                                                {"status", "running"},
                                                {"run_id", context.run_id},
                                                {"spec", spec.document}}
                                         .dump(1) +
                                     "\n");

  std::map<std::string, ResultRow> stored;
  for (const ResultRow& r : recorder.rows()) stored[r.run_name] = r;
  EvaluationSession session(spec.sweep.reference, spec.sweep.timing);
  std::unique_ptr<EvaluationSession> retime_session;  // 2 x repetitions, made on first need
  const int repetitions = spec.sweep.timing.repetitions;
  const TuneSpace space = make_tune_space(spec);
  std::map<std::string, TrialRecord> records;  // by overrides.dump()
  size_t computed = 0, reused = 0, retimed = 0;

  // The frames of the point measure_and_score measured last: its record's, when store_row stores
  // its row (the frames.csv written beside it holds the same).
  std::vector<FrameRow> last_frames;
  auto store_row = [&](ResultRow row) {
    PointRecord point{.row = std::move(row), .frames = std::move(last_frames), .images = {}};
    last_frames.clear();
    row = recorder.record(std::move(point));  // stamped with the run; SQLite, then the files
    stored[row.run_name] = row;
    return row;
  };
  // A point through the sweep's own steps (sweep_runner.cpp): a sequence point runs through the
  // session's frames (frames.cpp) and its frames.csv is written before its row is stored.
  auto measure_and_score = [&](EvaluationSession& s, const SweepPoint& p) {
    Measurement measured = s.measure(evaluation_request(p));
    ResultRow row = s.score(measured);
    if (!measured.frames.empty())
      write_text(frames_csv_path(out, p.name), frames_csv(measured.frames));
    last_frames = frame_rows(measured.frames);
    return row;
  };
  Progress progress("tune " + spec.name, static_cast<size_t>(spec.evaluations));
  const EvaluateFn evaluate = [&](const nlohmann::json& overrides) {
    SweepSpec one = spec.sweep;
    one.runs[0].fixed = overrides;
    const std::vector<SweepPoint> points = expand_sweep(one);
    std::vector<ResultRow> rows;
    TrialRecord record;
    for (const SweepPoint& p : points) {
      record.run_names.push_back(p.name);
      if (const auto it = stored.find(p.name); it != stored.end()) {
        rows.push_back(it->second);
        ++reused;
        continue;
      }
      if (interrupt_requested()) throw SearchStopped{};
      rows.push_back(store_row(measure_and_score(session, p)));
      ++computed;
    }
    Outcome outcome;
    for (const ResultRow& r : rows)
      if (r.status != "ok") {
        outcome.ok = false;
        record.status = r.status;
      }
    if (outcome.ok) {
      auto samples = [&] {
        std::vector<std::vector<double>> s;
        for (const ResultRow& r : rows) s.push_back(r.time_ms_samples);
        return s;
      };
      bool all_retimed = true;
      for (const ResultRow& r : rows)
        all_retimed = all_retimed && r.repetitions > first_samples(r, repetitions);
      record.time = judge_time(samples(), spec.budget_ms, all_retimed);
      if (record.time.verdict == TimeVerdict::borderline) {
        if (!retime_session)
          retime_session = std::make_unique<EvaluationSession>(
              spec.sweep.reference, TimingSpec{spec.sweep.timing.warmup, 2 * repetitions});
        for (size_t v = 0; v < rows.size(); ++v) {
          // Re-timed before an interruption.
          if (rows[v].repetitions > first_samples(rows[v], repetitions)) continue;
          if (interrupt_requested()) throw SearchStopped{};
          // A sequence point runs its frames once more (one sample a frame); a still view
          // 2 x repetitions more frames.
          rows[v] = store_row(pooled(rows[v], measure_and_score(*retime_session, points[v])));
        }
        ++retimed;
        record.time = judge_time(samples(), spec.budget_ms, true);
      }
      record.retimed = false;
      for (const ResultRow& r : rows)
        record.retimed = record.retimed || r.repetitions > first_samples(r, repetitions);
      double sum = 0.0;
      for (const ResultRow& r : rows)
        for (const std::string& term : spec.objective_terms) {  // a sum's terms, or the one key
          const bool true_key = term.rfind("true_", 0) == 0;
          sum += objective_of(r, true_key ? r.true_metrics : r.metrics,
                              true_key ? term.substr(5) : term, spec.objective, o.spec_path);
        }
      record.objective = sum / static_cast<double>(rows.size());
      outcome.objective = spec.maximise ? -record.objective : record.objective;
      outcome.time_ms = record.time.mean_median;
      outcome.feasible = record.time.verdict == TimeVerdict::feasible;
    } else {
      outcome.feasible = false;
    }
    records[overrides.dump()] = record;
    progress.step(points.empty() ? "" : points.front().name);
    return outcome;
  };

  SearchSettings settings;
  settings.algorithm = spec.algorithm;
  settings.evaluations = spec.evaluations;
  settings.seed = spec.seed;
  settings.budget_ms = spec.budget_ms;
  SearchResult result;
  try {
    // SIGINT stops the search between two points (the evaluate callback asks); the handler it
    // replaced is back before tune.json is written, whichever way the search ends.
    const InterruptScope interrupts;
    result = search(space, settings, evaluate);
  } catch (const std::exception& e) {
    // A tune that fails says so in tune.json instead of staying "running"; its rows are kept, and
    // the same command resumes from them once the cause is fixed (from the journal, should this
    // rewrite of results.json fail too).
    try {
      recorder.write_files();
    } catch (const std::exception&) {
    }
    write_text(tune_json.string(), nlohmann::json{{"name", spec.name},
                                                  {"status", "failed"},
                                                  {"error", e.what()},
                                                  {"run_id", context.run_id},
                                                  {"spec", spec.document}}
                                           .dump(1) +
                                       "\n");
    throw;
  }

  recorder.write_files();  // every row in results.json (record() appended them to the journal)
  // tune.json: written whole, atomically, at the end (and as "interrupted" when stopped).
  nlohmann::json trials = nlohmann::json::array();
  for (size_t i = 0; i < result.trials.size(); ++i)
    trials.push_back(
        trial_json(spec, result.trials[i], records.at(result.trials[i].overrides.dump()), i));
  const bool feasible = result.best >= 0;
  nlohmann::json doc = {
      {"schema_version", 1},
      {"name", spec.name},
      {"status", result.stopped ? "interrupted" : "complete"},
      {"run_id", context.run_id},
      {"estimator", spec.estimator->name},
      {"objective",
       {{"key", spec.objective},
        {"direction", spec.maximise ? "maximise" : "minimise"},
        {"over",
         "the mean over the spec's views (" +
             std::to_string(result.trials.empty() ? 0 : records.begin()->second.run_names.size()) +
             " rows a point)"}}},
      {"budget_ms", spec.budget_ms > 0.0 ? nlohmann::json(spec.budget_ms) : nlohmann::json()},
      {"feasible", feasible},
      {"best", nlohmann::json()},
      {"evaluations",
       {{"budget", spec.evaluations},
        {"used", result.trials.size()},
        {"rows_computed", computed},
        {"rows_reused", reused},
        {"retimed", retimed},
        {"optimiser_calls", result.calls}}},
      {"optimiser", result.settings},
      {"budget_rule",
       "time = mean over views of the median frame time (a sequence's: of its per-frame times); "
       "feasible when the mean of the slowest "
       "repetitions <= budget, infeasible when the mean of the fastest > budget; otherwise the "
       "point is re-timed once (2 x repetitions more frames, pooled; a sequence: its frames once "
       "more) and feasible when the pooled "
       "mean median <= budget"},
      {"noise",
       {{"objective", std::all_of(spec.objective_terms.begin(), spec.objective_terms.end(),
                                  [](const std::string& k) {
                                    return k.size() >= 11 &&
                                           k.compare(k.size() - 11, 11, "rmse_excess") == 0;
                                  })
                          ? spec.objective + ": the reference's own noise (AO_stderr) removed"
                          : "as the metric reads (the reference's noise not removed)"},
        {"seed", "every point runs with the same estimator seed (common random numbers): " +
                     (spec.estimator->find_param("seed")
                          ? resolve_params(spec.estimator->name, spec.estimator->params, spec.fixed,
                                           spec.name)
                                .json()["seed"]
                                .dump()
                          : std::string("the estimator has none"))},
        {"rounding", "reals to 3 significant digits, integers to the nearest"}}},
      {"trials", trials},
      {"spec", spec.document}};
  if (feasible) {
    const auto b = static_cast<size_t>(result.best);
    doc["best"] =
        point_json(spec, result.trials[b], records.at(result.trials[b].overrides.dump()), b);
  } else {
    int fastest = -1;
    for (size_t i = 0; i < result.trials.size(); ++i)
      if (result.trials[i].outcome.ok &&
          (fastest < 0 || result.trials[i].outcome.time_ms <
                              result.trials[static_cast<size_t>(fastest)].outcome.time_ms))
        fastest = static_cast<int>(i);
    if (fastest >= 0) {
      const auto f = static_cast<size_t>(fastest);
      doc["fastest"] =
          point_json(spec, result.trials[f], records.at(result.trials[f].overrides.dump()), f);
    }
  }
  write_text(tune_json.string(), doc.dump(1) + "\n");
  if (o.plot && !result.trials.empty()) {
    std::vector<TunePlotPoint> plotted;
    for (size_t i = 0; i < result.trials.size(); ++i) {
      const Trial& t = result.trials[i];
      const TrialRecord& r = records.at(t.overrides.dump());
      if (!t.outcome.ok) continue;
      double noise = 0.0;
      for (const std::string& name : r.run_names)
        if (const auto row = stored.find(name); row != stored.end())
          noise += pareto_time_noise(row->second);
      plotted.push_back(
          {r.objective, r.time.mean_median, r.time.mean_min, r.time.mean_max,
           r.run_names.empty() ? 0.0 : noise / static_cast<double>(r.run_names.size()),
           t.outcome.feasible, static_cast<int>(i) == result.best});
    }
    render_tune_plot(spec, plotted, (fs::path(out) / "tune.png").string());
  }

  if (result.stopped) {
    std::fprintf(stderr,
                 "tune %s: interrupted after %zu of %d evaluations; run the same command again to "
                 "continue\n",
                 spec.name.c_str(), result.trials.size(), spec.evaluations);
    return 130;
  }
  std::fprintf(stderr, "tune %s: %zu evaluations (%zu rows computed, %zu reused, %zu re-timed)\n",
               spec.name.c_str(), result.trials.size(), computed, reused, retimed);
  if (!feasible) {
    std::fprintf(
        stderr, "tune %s: no feasible point: none of %zu evaluations met the budget of %g ms%s\n",
        spec.name.c_str(), result.trials.size(), spec.budget_ms,
        doc.contains("fastest")
            ? (" (the fastest took " + format_param_value(doc["fastest"]["time_ms"]) + " ms)")
                  .c_str()
            : "");
  } else {
    const auto& best = doc["best"];
    std::printf("best %s = %.6g at %.4g ms: %s\n", spec.objective.c_str(),
                best["objective"].get<double>(), best["time_ms"].get<double>(),
                best["params"].dump().c_str());
  }
  std::printf("%s\n", tune_json.string().c_str());
  return 0;
}

}  // namespace aoeval
