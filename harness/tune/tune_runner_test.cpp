// `aoeval tune` end to end on the test-only synthetic estimator
// (estimators/testing/synthetic_tune_estimator.h), whose error and time are closed-form: on an open
// plane (two views, 16x12) the tuner must find the known optimum under the budget, judge a point
// exactly at the budget by re-timing it, write every evaluation as a results row, continue an
// interrupted tune from its rows when the same command runs again, and say when no point is
// feasible.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "base/json_reader.h"
#include "base/testing/test_temp_dir.h"
#include "estimators/testing/synthetic_tune_estimator.h"
#include "harness/results/results_store.h"
#include "harness/tune/tune_runner.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using testing_support::synthetic_error;
using testing_support::synthetic_frame_hook;
using testing_support::synthetic_lookup;

const std::string kPlane = std::string(AOEVAL_SOURCE_DIR) + "/harness/tune/testdata/plane.json";

fs::path write_spec(const fs::path& dir, nlohmann::json tune) {
  const nlohmann::json spec = {{"name", "synthetic"},
                               {"scenes", {kPlane}},
                               {"views", "all"},
                               {"reference", {{"spp", 4}, {"sampler", "sobol"}}},
                               {"timing", {{"warmup", 0}, {"repetitions", 3}}},
                               {"tune", std::move(tune)}};
  fs::create_directories(dir);
  const fs::path p = dir / "spec.json";
  std::ofstream(p) << spec.dump(1);
  return p;
}

nlohmann::json synthetic_tune(int evaluations = 60, double budget = 20.0) {
  return {{"estimator", "tune-synthetic"},
          {"params", {{"x", {0.01, 10.0}}, {"n", {1, 64}}, {"mode", "all"}, {"flag", "all"}}},
          {"objective", "rmse_excess"},
          {"budget_ms", budget},
          {"evaluations", evaluations}};
}

struct Tuned {
  int status = -1;
  nlohmann::json tune, results;
};

Tuned tune(const fs::path& spec, const fs::path& out) {
  setenv("AOEVAL_CACHE", (out.parent_path() / "cache").c_str(), 1);
  TuneOptions o;
  o.spec_path = spec.string();
  o.out_dir = out.string();
  o.database = (out.parent_path() / "results.sqlite").string();
  o.plot = false;
  o.lookup = synthetic_lookup;
  Tuned t;
  t.status = run_tune(o);
  t.tune = parse_json_file((out / "tune.json").string());
  t.results = parse_json_file((out / "results.json").string());
  return t;
}

TEST(TuneRunner, FindsTheKnownOptimumUnderTheBudget) {
  const fs::path d = testutil::test_temp_dir("tune");
  const Tuned t = tune(write_spec(d, synthetic_tune()), d / "out");
  ASSERT_EQ(t.status, 0);
  const auto& best = t.tune["best"];
  ASSERT_TRUE(t.tune["feasible"].get<bool>()) << t.tune.dump(1);
  EXPECT_EQ(best["params"]["n"], 19) << best.dump();
  EXPECT_EQ(best["params"]["mode"], "b");
  EXPECT_EQ(best["params"]["flag"], false);
  const double x = best["params"]["x"];
  // The objective the rows report is the closed form at the point found (float AO: 1e-6), and
  // within 1e-3 of the optimum 0.02 + 0.4 / 19 (|log10(x / 0.5)| < 0.1).
  EXPECT_NEAR(best["objective"].get<double>(), synthetic_error(x, 19, "b", false), 1e-6);
  EXPECT_NEAR(best["objective"].get<double>(), 0.02 + 0.4 / 19.0, 1e-3);
  EXPECT_DOUBLE_EQ(best["time_ms"].get<double>(), 19.5);
  EXPECT_LE(t.tune["evaluations"]["used"].get<int>(), 60);
  // Every evaluation is two rows (one per view), each a normal results row.
  EXPECT_EQ(t.results["rows"].size(), 2 * t.tune["evaluations"]["used"].get<size_t>());
  EXPECT_EQ(t.tune["evaluations"]["rows_computed"].get<size_t>(), t.results["rows"].size());
  SqliteStore db((d / "results.sqlite").string());
  EXPECT_EQ(db.rows_of_run(t.tune["run_id"]).size(), t.results["rows"].size());
  EXPECT_EQ(t.tune["optimiser"]["algorithm"], "direct-l+sbplx");
  EXPECT_EQ(t.tune["status"], "complete");
}

// n = 39 in mode a takes exactly 20 ms, its frames 19.6 to 20.4: the budget lies in the spread, so
// the point is re-timed (6 more frames a view, kept in the row) and judged by its pooled median.
TEST(TuneRunner, ReTimesAPointAtTheBudgetAndKeepsEverySample) {
  const fs::path d = testutil::test_temp_dir("tune");
  nlohmann::json t = synthetic_tune(3);
  t["params"] = {{"x", {0.4, 0.6}}};
  t["fixed"] = {{"n", 39}, {"mode", "a"}};
  const Tuned r = tune(write_spec(d, t), d / "out");
  ASSERT_EQ(r.status, 0);
  ASSERT_TRUE(r.tune["feasible"].get<bool>());
  for (const auto& trial : r.tune["trials"]) {
    EXPECT_TRUE(trial["retimed"].get<bool>());
    EXPECT_DOUBLE_EQ(trial["time_ms"].get<double>(), 20.0);
  }
  for (const auto& row : r.results["rows"]) EXPECT_EQ(row["repetitions"], 9);
  EXPECT_EQ(r.tune["evaluations"]["retimed"], r.tune["evaluations"]["used"]);
}

TEST(TuneRunner, SaysWhenNoPointMeetsTheBudget) {
  const fs::path d = testutil::test_temp_dir("tune");
  const Tuned r = tune(write_spec(d, synthetic_tune(8, 0.5)), d / "out");
  ASSERT_EQ(r.status, 0);
  EXPECT_FALSE(r.tune["feasible"].get<bool>());
  EXPECT_TRUE(r.tune["best"].is_null());
  // The fastest point tried is n = 1 in mode a (1 ms) or b (1.5 ms) if the search reached it.
  ASSERT_TRUE(r.tune.contains("fastest"));
  EXPECT_GT(r.tune["fastest"]["time_ms"].get<double>(), 0.5);
}

// SIGINT mid-way (raised from inside a frame): exit 130, tune.json "interrupted", every finished
// row kept. The same command again continues: the search replays the same points, reads the rows
// it has, computes the rest, and ends where an uninterrupted tune ends.
TEST(TuneRunner, ContinuesAnInterruptedTuneFromItsRows) {
  const fs::path d = testutil::test_temp_dir("tune");
  const fs::path spec = write_spec(d, synthetic_tune(24));
  const Tuned whole = tune(spec, d / "whole");
  ASSERT_EQ(whole.status, 0);

  int frames = 0;
  synthetic_frame_hook() = [&] {
    if (++frames == 60) std::raise(SIGINT);  // a few points in (re-timed ones take 9 frames a view)
  };
  const Tuned first = tune(spec, d / "resumed");
  synthetic_frame_hook() = nullptr;
  ASSERT_EQ(first.status, 130);
  EXPECT_EQ(first.tune["status"], "interrupted");
  const size_t kept = first.results["rows"].size();
  EXPECT_GT(kept, 0u);
  EXPECT_LT(kept, whole.results["rows"].size());

  const Tuned second = tune(spec, d / "resumed");
  ASSERT_EQ(second.status, 0);
  EXPECT_EQ(second.tune["status"], "complete");
  EXPECT_EQ(second.tune["evaluations"]["rows_reused"].get<size_t>(), kept);
  EXPECT_EQ(second.tune["run_id"], first.tune["run_id"]);  // one tune, one run
  ASSERT_EQ(second.tune["trials"].size(), whole.tune["trials"].size());
  for (size_t i = 0; i < whole.tune["trials"].size(); ++i) {
    EXPECT_EQ(second.tune["trials"][i]["params"], whole.tune["trials"][i]["params"]) << i;
    EXPECT_EQ(second.tune["trials"][i]["objective"], whole.tune["trials"][i]["objective"]) << i;
  }
  EXPECT_EQ(second.tune["best"]["params"], whole.tune["best"]["params"]);
  EXPECT_EQ(second.results["rows"].size(), whole.results["rows"].size());

  // A third run computes nothing.
  const Tuned third = tune(spec, d / "resumed");
  EXPECT_EQ(third.tune["evaluations"]["rows_computed"], 0);

  // Another spec in the same folder is refused before anything is touched.
  const fs::path other = write_spec(d / "other", synthetic_tune(30));
  EXPECT_THROW(tune(other, d / "resumed"), InputError);
}

// A real tune over a sequence (CONTRACT §8 and §10): raytraced's rays on an 8-frame static box at
// 32x24 scored by temporal_rmse_excess. Every point runs through the temporal runner (a sequence
// row, one time sample a frame, its frames.csv beside it), and the objective each trial reports is
// its row's temporal_rmse_excess, not the last frame's rmse_excess.
TEST(TuneRunner, TunesASequenceScoreThroughTheTemporalRunner) {
  const fs::path d = testutil::test_temp_dir("tune_sequence");
  const fs::path scene = d / "still.json";
  std::ofstream(scene) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.6, 0.6, 0.6]},
       "transform": {"translate": [0, 0.3, 0]}}],
    "views": [{"name": "still", "eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0], "fov_y_deg": 50,
               "width": 32, "height": 24, "sequence": {"frames": 8}}]})";
  const nlohmann::json doc = {{"name", "sequence"},
                              {"scenes", {scene.string()}},
                              {"views", {"still"}},
                              {"reference", {{"spp", 16}, {"sampler", "sobol"}}},
                              {"timing", {{"warmup", 0}, {"repetitions", 3}}},
                              {"tune",
                               {{"estimator", "raytraced"},
                                {"params", {{"rays", {1, 8}}}},
                                {"fixed", {{"sampler", "random"}}},
                                {"objective", "temporal_rmse_excess"},
                                {"budget_ms", 1e6},
                                {"evaluations", 3}}}};
  const fs::path spec = d / "spec.json";
  std::ofstream(spec) << doc.dump(1);
  setenv("AOEVAL_CACHE", (d / "cache").c_str(), 1);
  TuneOptions o;
  o.spec_path = spec.string();
  o.out_dir = (d / "out").string();
  o.database = (d / "results.sqlite").string();
  o.plot = false;
  ASSERT_EQ(run_tune(o), 0);
  const nlohmann::json t = parse_json_file((d / "out" / "tune.json").string());
  const nlohmann::json rows = parse_json_file((d / "out" / "results.json").string())["rows"];
  EXPECT_EQ(t["objective"]["key"], "temporal_rmse_excess");
  ASSERT_EQ(t["trials"].size(), 3u);
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& trial : t["trials"]) {
    const std::string name = trial["run_names"][0];
    nlohmann::json row;
    for (const auto& r : rows)
      if (r["run_name"] == name) row = r;
    ASSERT_FALSE(row.is_null()) << name;
    const auto& m = row;  // results.json rows are flat (CONTRACT §4)
    EXPECT_EQ(m["seq_frames"], 8);
    EXPECT_EQ(row["repetitions"], 8);  // one timed run per frame, not re-timed
    EXPECT_FALSE(trial["retimed"].get<bool>());
    EXPECT_EQ(trial["objective"].get<double>(), m["temporal_rmse_excess"].get<double>());
    EXPECT_NE(trial["objective"].get<double>(), m["rmse_excess"].get<double>());
    EXPECT_TRUE(fs::exists(d / "out" / "sequences" / file_stem_for(name) / "frames.csv")) << name;
  }
  EXPECT_TRUE(t["feasible"].get<bool>());
  // The flicker of a mean of n Bernoulli visibilities falls as 1/sqrt(n): the best point found is
  // the one with most rays.
  int most = 0;
  for (const auto& trial : t["trials"]) most = std::max(most, trial["params"]["rays"].get<int>());
  EXPECT_EQ(t["best"]["params"]["rays"], most);

  // A sum objective scores each trial by the sum of its row's keys.
  nlohmann::json summed = doc;
  summed["tune"]["objective"] = "temporal_rmse_excess+seq_rmse_excess";
  std::ofstream(spec) << summed.dump(1);
  o.out_dir = (d / "summed").string();
  ASSERT_EQ(run_tune(o), 0);
  const nlohmann::json st = parse_json_file((d / "summed" / "tune.json").string());
  const nlohmann::json srows = parse_json_file((d / "summed" / "results.json").string())["rows"];
  ASSERT_EQ(st["trials"].size(), srows.size());
  for (const auto& trial : st["trials"]) {
    for (const auto& r : srows) {
      if (r["run_name"] != trial["run_names"][0]) continue;
      EXPECT_DOUBLE_EQ(trial["objective"].get<double>(), r["temporal_rmse_excess"].get<double>() +
                                                             r["seq_rmse_excess"].get<double>());
    }
  }

  // The budget bounds the per-frame time (the trials' time_ms is a median frame time): below any
  // frame's time no point is feasible, and the tune still ends 0 with no best point.
  nlohmann::json tight = doc;
  tight["tune"]["budget_ms"] = 1e-6;
  std::ofstream(spec) << tight.dump(1);
  o.out_dir = (d / "tight").string();
  ASSERT_EQ(run_tune(o), 0);
  const nlohmann::json tt = parse_json_file((d / "tight" / "tune.json").string());
  EXPECT_FALSE(tt["feasible"].get<bool>());
  for (const auto& trial : tt["trials"]) EXPECT_FALSE(trial["feasible"].get<bool>());
}

}  // namespace
}  // namespace aoeval
