// `aoeval dashboard` as CI uses it (CONTRACT §2): a tiny sweep run twice -> exit 0; run again with
// one estimator's parameter made worse -> exit 1, naming the estimator and the scene;
// bad input -> exit 2 with one line. Timing is left out here (a threshold no timing can pass
// in --config): timings on a shared CI machine are not what this test checks, and the rank test is
// unit-tested in reports/regression_test.cpp.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/cli/cli_test_util.h"
#include "scenes/test_temp_dir.h"

namespace {

namespace fs = std::filesystem;

using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

class DashboardCli : public ::testing::Test {
 protected:
  fs::path dir = aoeval::testutil::test_temp_dir("dashboard_cli");
  void SetUp() override {
    // Two estimators on a small view: the constant (deterministic, no rays) and raytraced; the
    // same sweep name with raytraced made worse (1 ray instead of 8).
    for (const auto& [file, rays] : {std::pair{"tiny.json", 8}, std::pair{"tiny_worse.json", 1}}) {
      std::ofstream(dir / file) << R"({"name": "tiny", "scenes": ["cornell-box"],
        "res": [48, 36], "reference": {"spp": 16, "sampler": "sobol"},
        "timing": {"warmup": 1, "repetitions": 5},
        "runs": [{"estimator": "constant"},
                 {"estimator": "raytraced", "fixed": {"rays": )"
                                << rays << "}}]}";
    }
    std::ofstream(dir / "accuracy_only.json")
        << R"({"comment": "timing excluded", "defaults": {"time_relative": 1000}})";
  }
  Result run(const std::string& args) {
    // Its own reference cache: the test neither reads nor fills the user's.
    return aoeval::cli_test::run_aoeval(
        "cd " + dir.string() + " && AOEVAL_CACHE=" + (dir / "cache").string() + " ", args, dir);
  }
  // History charts cost a python process per call: drawn once, in the regression check.
  Result dashboard(bool charts = false) {
    return run(std::string("dashboard --db r.sqlite --out dash --config accuracy_only.json") +
               (charts ? "" : " --no-charts"));
  }
};

TEST_F(DashboardCli, UnchangedRerunPassesAndAWorseParameterFails) {
  ASSERT_EQ(run("sweep tiny.json --out a --db r.sqlite").code, 0);
  // One run: nothing to compare with yet.
  Result first = dashboard();
  EXPECT_EQ(first.code, 0) << first.out << first.err;
  EXPECT_NE(first.out.find("no earlier run"), std::string::npos) << first.out;

  ASSERT_EQ(run("sweep tiny.json --out b --db r.sqlite").code, 0);
  Result same = dashboard();
  EXPECT_EQ(same.code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("0 regressed"), std::string::npos) << same.out;
  EXPECT_NE(same.out.find("2 unchanged"), std::string::npos) << same.out;
  EXPECT_TRUE(fs::exists(dir / "dash" / "index.html"));

  // raytraced with 1 ray instead of 8: its error roughly doubles.
  ASSERT_EQ(run("sweep tiny_worse.json --out c --db r.sqlite").code, 0);
  Result worse = dashboard(true);
  EXPECT_EQ(worse.code, 1) << worse.out << worse.err;
  EXPECT_NE(worse.out.find("REGRESSED raytraced scene cornell-box"), std::string::npos)
      << worse.out;
  EXPECT_NE(worse.out.find("rays: 8 -> 1"), std::string::npos) << worse.out;
  EXPECT_EQ(worse.out.find("REGRESSED constant"), std::string::npos) << worse.out;
  const std::string page = slurp(dir / "dash" / "index.html");
  EXPECT_NE(page.find("raytraced on cornell-box"), std::string::npos);
  EXPECT_NE(page.find("class=\"chart\""), std::string::npos);

  // Against the first run explicitly: the same regression.
  const std::string first_id = [&] {
    const std::string json = slurp(dir / "a" / "results.json");
    const auto at = json.find("\"run_id\"");
    const auto q1 = json.find('"', json.find(':', at) + 1);
    return json.substr(q1 + 1, json.find('"', q1 + 1) - q1 - 1);
  }();
  Result explicit_baseline = run(
      "dashboard --db r.sqlite --out dash2 --no-charts --config accuracy_only.json --baseline " +
      first_id);
  EXPECT_EQ(explicit_baseline.code, 1) << explicit_baseline.out << explicit_baseline.err;
  EXPECT_NE(explicit_baseline.out.find(first_id), std::string::npos) << explicit_baseline.out;
}

TEST_F(DashboardCli, BadInputExitsTwoWithOneLine) {
  for (const std::string& args :
       {std::string("dashboard --db absent.sqlite --out d"),
        std::string("dashboard --db absent.sqlite --config missing.json")}) {
    Result r = run(args);
    EXPECT_EQ(r.code, 2) << args << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "absent.sqlite"));
  std::ofstream(dir / "bad.json") << R"({"defaults": {"rmse_sigma": 3}})";
  ASSERT_EQ(run("sweep tiny.json --out a --db r.sqlite").code, 0);
  Result r = run("dashboard --db r.sqlite --config bad.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bad.json: defaults.rmse_sigma"), std::string::npos) << r.err;
  r = run("dashboard --db r.sqlite --baseline nope");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--baseline nope"), std::string::npos) << r.err;
}

}  // namespace
