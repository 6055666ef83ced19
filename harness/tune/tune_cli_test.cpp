// `aoeval tune` through the binary: bad input exits 2 with one line naming the field and leaves no
// output behind; a budget no point can meet exits 0 with "no feasible point" on stderr and
// "feasible": false in tune.json; a plug-in's declared ranges are checked like a built-in's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

const std::string kPlane = std::string(AOEVAL_SOURCE_DIR) + "/harness/tune/testdata/plane.json";

nlohmann::json spec_with(nlohmann::json tune) {
  return {{"name", "cli"},
          {"scenes", {kPlane}},
          {"reference", {{"spp", 4}}},
          {"timing", {{"warmup", 0}, {"repetitions", 3}}},
          {"tune", std::move(tune)}};
}

nlohmann::json constant_tune() {
  return {{"estimator", "constant"},
          {"params", {{"value", {0.5, 1.0}}}},
          {"objective", "rmse_excess"},
          {"budget_ms", 1000},
          {"evaluations", 4}};
}

Result tune(const fs::path& d, const nlohmann::json& spec) {
  std::ofstream(d / "spec.json") << spec.dump(1);
  return aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " ",
                                      "tune " + (d / "spec.json").string() + " --out " +
                                          (d / "out").string() + " --db " +
                                          (d / "db.sqlite").string(),
                                      d);
}

void expect_bad_input(const std::string& key, nlohmann::json value, const std::string& says) {
  const fs::path d = aoeval::testutil::test_temp_dir("tune_cli_" + key);
  nlohmann::json t = constant_tune();
  if (key.rfind("params.", 0) == 0)
    t["params"][key.substr(7)] = value;
  else
    t[key] = value;
  const Result r = tune(d, spec_with(t));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("tune." + key), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(d / "out"));
  EXPECT_FALSE(fs::exists(d / "db.sqlite"));
}

TEST(TuneCli, UnknownParameterIsExit2NamingIt) {
  expect_bad_input("params.valu", {0.1, 0.2}, "unknown parameter of constant (known: value)");
}

TEST(TuneCli, RangeOutsideTheDeclarationIsExit2NamingIt) {
  expect_bad_input("params.value", {0.5, 2.0}, "outside the declared range [0, 1]");
}

TEST(TuneCli, UnknownObjectiveIsExit2NamingIt) {
  expect_bad_input("objective", "rmse_excesss", "is not a metric key");
}

TEST(TuneCli, APlugInsDeclaredRangeIsCheckedLikeABuiltIns) {
  // plugins/examples/sao declares its parameters in its manifest; the registry reads them.
  const fs::path d = aoeval::testutil::test_temp_dir("tune_cli_plugin");
  nlohmann::json t = constant_tune();
  t["estimator"] = "sao";
  t["params"] = {{"radius", {0.1, 1e9}}};
  const Result r = tune(d, spec_with(t));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("tune.params.radius"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("declared range"), std::string::npos) << r.err;
}

TEST(TuneCli, ABudgetNoPointMeetsIsExit0WithNoFeasiblePoint) {
  const fs::path d = aoeval::testutil::test_temp_dir("tune_cli");
  nlohmann::json t = constant_tune();
  t["budget_ms"] = 1e-6;  // a frame of anything takes longer than a nanosecond
  const Result r = tune(d, spec_with(t));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("no feasible point"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(d / "out/tune.json"));
  EXPECT_FALSE(j["feasible"].get<bool>());
  EXPECT_TRUE(j["best"].is_null());
  EXPECT_TRUE(j.contains("fastest"));
  EXPECT_EQ(j["evaluations"]["used"], 4);
  EXPECT_TRUE(fs::exists(d / "out/results.csv"));
  EXPECT_TRUE(fs::exists(d / "out/tune.png"));
  EXPECT_TRUE(fs::exists(d / "out/tune.png.plot.json"));
}

}  // namespace
