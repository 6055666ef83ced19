// `aoeval tune` end to end on the test-only synthetic estimator
// (estimators/testing/synthetic_tune_estimator.h), whose error and time are closed-form: on an open
// plane (two views, 16x12) the tuner must find the known optimum under the budget, judge a point
// exactly at the budget by re-timing it, write every evaluation as a results row, continue an
// interrupted tune from its rows when the same command runs again, and say when no point is
// feasible.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "estimators/testing/synthetic_tune_estimator.h"
#include "harness/results/results_store.h"
#include "harness/tune/tune_runner.h"
#include "json_reader.h"
#include "scenes/test_temp_dir.h"

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

}  // namespace
}  // namespace aoeval
