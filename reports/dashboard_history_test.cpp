// Changes and history on synthetic runs (no estimator runs): an estimate darkened by 0.9 is
// CHANGED on every row whatever its error did, warn or fail as configured; eight runs whose
// estimates step at the fifth give exactly one step per affected series, at that run.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "reports/dashboard.h"
#include "reports/dashboard_test_util.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using testutil::FakeRow;
using testutil::History;

std::vector<FakeRow> plugin_rows(double scale, double rmse_excess, double time_ms = 1.0) {
  std::vector<FakeRow> rows;
  for (double r : {0.5, 1.0}) {
    FakeRow f;
    f.estimator = "vo-loos";
    f.params = {{"R", r}, {"samples", 8}};
    f.scale = scale;
    f.rmse_excess = rmse_excess;
    f.time_ms = time_ms;
    rows.push_back(f);
  }
  FakeRow steady;
  steady.estimator = "constant";
  steady.time_ms = time_ms;
  rows.push_back(steady);
  return rows;
}

TEST(DashboardChanges, ADarkenedEstimateIsChangedOnEveryRowAndFailsOnlyWhenAsked) {
  History h("changes");
  h.add_rows("r1", "2024-01-01T00:00:00Z", plugin_rows(1.0, 0.05));
  // Darker by 10 %: its error even falls (a bright-biased estimator), so nothing regressed.
  h.add_rows("r2", "2024-01-02T00:00:00Z", plugin_rows(0.9, 0.03));
  DashboardOptions o = h.options();
  o.estimator_defaults["vo-loos"] = {{"R", 0.5}, {"samples", 8}};
  const Dashboard d = build_dashboard(o);
  EXPECT_EQ(d.regressed, 0);
  EXPECT_EQ(d.changed, 2);
  EXPECT_FALSE(dashboard_fails(d));
  std::vector<std::string> changed;
  for (const auto& line : console_lines(d))
    if (line.rfind("CHANGED ", 0) == 0) changed.push_back(line);
  ASSERT_EQ(changed.size(), 2u);
  std::sort(changed.begin(), changed.end());
  // R differs from its default in one row only: that row names it first (samples=8 is default).
  EXPECT_EQ(changed[1].find("CHANGED vo-loos R=1,samples=8 scene bunny view main 24x16: darker by "
                            "0.0"),
            0u)
      << changed[1];
  EXPECT_NE(changed[1].find(" mean AO on 100 % of pixels"), std::string::npos) << changed[1];
  EXPECT_EQ(changed[0].find("CHANGED vo-loos R=0.5,samples=8 scene bunny"), 0u) << changed[0];
  for (const auto& rep : d.rows) {
    if (rep.estimator != "vo-loos") continue;
    ASSERT_TRUE(rep.change);
    EXPECT_EQ(rep.change->noise_rule, "deterministic");
    EXPECT_NEAR(rep.change->mean_shift, -0.05, 0.005);
  }
  const std::string page = testutil::slurp(d.page);
  EXPECT_NE(page.find("id=\"changed\""), std::string::npos);
  EXPECT_NE(page.find("darker by 0.0"), std::string::npos);

  const fs::path fail = h.dir / "fail.json";
  std::ofstream(fail) << R"({"defaults": {"change_action": "fail"}})";
  o.config_path = fail.string();
  EXPECT_TRUE(dashboard_fails(build_dashboard(o)));
  // A per-estimator threshold above the shift: unchanged.
  std::ofstream(fail) << R"({"defaults": {"change_action": "fail"},
                            "estimators": {"vo-loos": {"change_mean_shift": 0.06}}})";
  const Dashboard quiet = build_dashboard(o);
  EXPECT_EQ(quiet.changed, 0);
  EXPECT_FALSE(dashboard_fails(quiet));
}

TEST(DashboardHistory, EightRunsSteppingAtTheFifthGiveOneStepPerAffectedSeries) {
  History h("history");
  std::mt19937_64 rng(5);
  std::normal_distribution<double> jitter(0.0, 0.05);
  std::vector<std::string> ids;
  for (int i = 1; i <= 8; ++i) {
    const bool after = i >= 5;
    const std::string id = "r" + std::to_string(i);
    const std::string commit = std::string(i < 10 ? "c0" : "c") + std::to_string(i) +
                               "00000000000000000000000000000000000000";
    h.add_rows(
        id, "2024-01-0" + std::to_string(i) + "T00:00:00Z",
        plugin_rows(after ? 0.9 : 1.0, after ? 0.0341 : 0.0210, 25.0 * std::exp(jitter(rng))),
        "sweep vo", commit);
    ids.push_back(id);
  }
  DashboardOptions o = h.options();
  o.history_steps = 8;
  o.charts = true;
  const Dashboard d = build_dashboard(o);
  ASSERT_TRUE(d.history_searched);
  EXPECT_EQ(d.history_size, 8u);
  // Two vo-loos rows x (rmse_excess, mean): four steps, all at r5; none for constant or times.
  ASSERT_EQ(d.steps.size(), 4u);
  for (const auto& s : d.steps) {
    EXPECT_EQ(s.run.run_id, "r5") << s.series << " " << s.figure;
    EXPECT_EQ(s.estimator, "vo-loos");
    EXPECT_NE(s.figure, "time_ms_median");
  }
  std::vector<std::string> step_lines;
  for (const auto& line : console_lines(d))
    if (line.rfind("STEP ", 0) == 0) step_lines.push_back(line);
  ASSERT_EQ(step_lines.size(), 4u);
  EXPECT_NE(std::find(step_lines.begin(), step_lines.end(),
                      "STEP vo-loos/R:0.5/samples:8/scene:bunny/view:main/24x16 at run r5 "
                      "(c05000000000): rmse_excess 0.0210 -> 0.0341"),
            step_lines.end())
      << step_lines[0];
  // The charts mark the step; the page lists it.
  bool marked = false;
  for (const auto& g : d.groups)
    for (const auto& chart : g.charts)
      if (testutil::slurp((fs::path(o.out_dir) / chart).string() + ".plot.json").find("\"step\"") !=
          std::string::npos)
        marked = true;
  EXPECT_TRUE(marked);
  EXPECT_NE(testutil::slurp(d.page).find("id=\"steps\""), std::string::npos);
}

// A sequence key steps: steady_rmse_excess 0.020 -> 0.032 from the fifth of eight runs, nothing
// else moves; exactly one step, in that key, at r5.
TEST(DashboardHistory, AStepInASequenceKeyIsFoundAtItsRun) {
  History h("sequence_history");
  for (int i = 1; i <= 8; ++i) {
    FakeRow f;
    f.estimator = "my-temporal";
    f.params = {{"R", 0.5}};
    f.more_metrics = {{"seq_frames", 16},
                      {"seq_rmse_excess", 0.03},
                      {"steady_rmse_excess", i >= 5 ? 0.032 : 0.020},
                      {"temporal_rmse_excess", 0.0129},
                      {"converge_frames", 4}};
    h.add_rows("r" + std::to_string(i), "2024-01-0" + std::to_string(i) + "T00:00:00Z", {f},
               "sweep seq");
  }
  DashboardOptions o = h.options();
  o.history_steps = 8;
  const Dashboard d = build_dashboard(o);
  ASSERT_EQ(d.steps.size(), 1u);
  EXPECT_EQ(d.steps[0].figure, "steady_rmse_excess");
  EXPECT_EQ(d.steps[0].run.run_id, "r5");
  std::vector<std::string> step_lines;
  for (const auto& line : console_lines(d))
    if (line.rfind("STEP ", 0) == 0) step_lines.push_back(line);
  ASSERT_EQ(step_lines.size(), 1u);
  EXPECT_EQ(step_lines[0],
            "STEP my-temporal/R:0.5/scene:bunny/view:main/24x16 at run r5 (0123456789ab): "
            "steady_rmse_excess 0.0200 -> 0.0320");
}

}  // namespace
}  // namespace aoeval
