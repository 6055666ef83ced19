// Runs past one machine (issue 19), through the aoeval binary: --shard auto, the reference cache
// under concurrent writers, the scanned meshes with a fresh cache, `aoeval merge` (rows once,
// conflicts named, a suite's report), and the shard planner. The Slurm round trip itself is
// slurm_cluster_test.sh (a real one-node cluster).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "base/errors.h"
#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"
#include "harness/sweep/shard_plan.h"
#include "scenes/scene.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

Result run(const fs::path& d, const std::string& env, const std::string& args) {
  fs::create_directories(d);
  return aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " " + env, args,
                                      d);
}

// Six cheap points: constant at three values and raytraced at two ray counts on cornell-box.
std::string write_spec(const fs::path& d) {
  const nlohmann::json spec = {
      {"name", "tiny"},
      {"scenes", {"cornell-box"}},
      {"res", {24, 24}},
      {"reference", {{"spp", 8}, {"sampler", "sobol"}}},
      {"timing", {{"warmup", 0}, {"repetitions", 1}}},
      {"runs",
       {{{"estimator", "constant"}, {"grid", {{"value", {0.2, 0.5, 0.8}}}}},
        {{"estimator", "raytraced"}, {"grid", {{"rays", {1, 2, 4}}}}}}}};
  fs::create_directories(d);
  std::ofstream(d / "tiny.json") << spec.dump(2);
  return (d / "tiny.json").string();
}

std::vector<std::string> run_names(const fs::path& results_json) {
  std::vector<std::string> names;
  const nlohmann::json doc = nlohmann::json::parse(slurp(results_json));
  for (const auto& r : doc["rows"]) names.push_back(r["run_name"].get<std::string>());
  return names;
}

TEST(ShardAuto, OutsideSlurmIsBadUsageAndInsideReadsTheArrayTask) {
  const fs::path d = aoeval::testutil::test_temp_dir("cluster");
  const std::string spec = write_spec(d);
  const Result outside = run(d, "env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT ",
                             "sweep " + spec + " --shard auto --out " + (d / "x").string());
  EXPECT_EQ(outside.code, 2) << outside.err;
  EXPECT_NE(outside.err.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << outside.err;
  EXPECT_FALSE(fs::exists(d / "x" / "results.json"));

  const Result bad = run(d, "SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_COUNT=2 ",
                         "sweep " + spec + " --shard auto --out " + (d / "y").string());
  EXPECT_EQ(bad.code, 2) << bad.err;

  const Result a = run(d, "SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 ",
                       "sweep " + spec + " --shard auto --db " + (d / "db.sqlite").string() +
                           " --out " + (d / "auto").string());
  ASSERT_EQ(a.code, 0) << a.err;
  const Result b = run(d, "",
                       "sweep " + spec + " --shard 1/2 --db " + (d / "db.sqlite").string() +
                           " --out " + (d / "explicit").string());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(run_names(d / "auto" / "results.json"), run_names(d / "explicit" / "results.json"));
  EXPECT_EQ(run_names(d / "auto" / "results.json").size(), 3u);
}

// Four processes ask for the same reference at once on an empty cache: one computes it (its lock
// holds the others), the others are served the finished file; every output is the same bytes and
// the cache holds the entry and its lock file only (no torn file, no leftover temporary).
TEST(ReferenceCache, ConcurrentProcessesComputeOnceAndNeverReadHalfAFile) {
  const fs::path d = aoeval::testutil::test_temp_dir("cluster");
  fs::create_directories(d / "cache");
  std::string cmd;
  for (int i = 0; i < 4; ++i)
    cmd += "(AOEVAL_CACHE=" + (d / "cache").string() + " " + AOEVAL_BINARY +
           " reference --scene cornell-box --res 48x48 --spp 64 -o " +
           (d / ("ref" + std::to_string(i) + ".exr")).string() + " 2>" +
           (d / ("err" + std::to_string(i))).string() + "; echo $? >" +
           (d / ("rc" + std::to_string(i))).string() + ") & ";
  cmd += "wait";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  int computed = 0, served = 0;
  for (int i = 0; i < 4; ++i) {
    const std::string n = std::to_string(i);
    EXPECT_EQ(slurp(d / ("rc" + n)), "0\n") << slurp(d / ("err" + n));
    const std::string err = slurp(d / ("err" + n));
    computed += err.find("Mrays traced") != std::string::npos;
    served += err.find("served from cache") != std::string::npos;
    EXPECT_EQ(slurp(d / ("ref" + n + ".exr")), slurp(d / "ref0.exr")) << i;
  }
  EXPECT_EQ(computed, 1);
  EXPECT_EQ(served, 3);
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(d / "cache" / "references"))
    files.insert(e.path().extension().string());
  EXPECT_EQ(files, (std::set<std::string>{".exr", ".lock"}));
}

// A node given a fresh, empty shared cache for its references still finds the scanned meshes its
// set-up extracted (scenes/scene.h mesh_data_dirs), and its references go to the fresh cache.
TEST(MeshData, AFreshEmptyCacheStillFindsBunny) {
  std::string data;
  for (const std::string& dir : aoeval::mesh_data_dirs())
    if (fs::exists(fs::path(dir) / "meshes" / "bunny00.off")) data = dir;
  if (data.empty()) GTEST_SKIP() << "bunny00.off is not extracted (run tools/bootstrap.sh)";
  const fs::path d = aoeval::testutil::test_temp_dir("cluster");
  const Result r = run(d, "AOEVAL_DATA=" + data + " ",
                       "reference --scene bunny --res 16x12 --spp 2 -o " + (d / "b.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::is_empty(d / "cache" / "references"));
  EXPECT_FALSE(fs::exists(d / "cache" / "meshes"));
  // Without AOEVAL_DATA the user's own cache folder is searched after the fresh AOEVAL_CACHE.
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  const fs::path user =
      xdg && *xdg ? fs::path(xdg) / "aoeval" : fs::path(home ? home : "") / ".cache" / "aoeval";
  if (std::getenv("AOEVAL_DATA") == nullptr && fs::path(data) == user) {
    const Result s = run(d, "", "scenes show bunny");
    EXPECT_EQ(s.code, 0) << s.err;
  }
}

TEST(Merge, EveryRowOnceDuplicatesKeptOnceConflictsNamed) {
  const fs::path d = aoeval::testutil::test_temp_dir("cluster");
  const std::string spec = write_spec(d);
  const std::string db = " --db " + (d / "db.sqlite").string();
  ASSERT_EQ(run(d, "", "sweep " + spec + db + " --out " + (d / "whole").string()).code, 0);
  for (int i = 0; i < 2; ++i) {
    const Result r = run(d, "",
                         "sweep " + spec + db + " --shard " + std::to_string(i) + "/2 --out " +
                             (d / ("s" + std::to_string(i))).string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  // A folder merged twice (the same rows) is kept once; the rows equal the single run's.
  const Result m = run(d, "",
                       "merge " + (d / "s0").string() + " " + (d / "s1").string() + " " +
                           (d / "s1").string() + " --out " + (d / "merged").string() + db);
  ASSERT_EQ(m.code, 0) << m.err;
  auto rows = [](const fs::path& f) {
    std::map<std::string, std::string> out;
    const nlohmann::json doc = nlohmann::json::parse(slurp(f));
    for (const auto& r : doc["rows"]) {
      nlohmann::json keep = r;
      for (const char* k : {"run_id", "timestamp", "time_ms_median", "time_ms_min", "time_ms_max",
                            "time_ms_samples", "estimate_file", "precompute_ms"})
        keep.erase(k);
      out[r["run_name"].get<std::string>()] = keep.dump();
    }
    return out;
  };
  const auto merged = rows(d / "merged" / "results.json");
  EXPECT_EQ(merged.size(), 6u);
  EXPECT_EQ(merged, rows(d / "whole" / "results.json"));
  EXPECT_TRUE(fs::exists(d / "merged" / "results.csv"));

  // The same row with another metric value in a second folder: exit 2 naming it.
  nlohmann::json changed = nlohmann::json::parse(slurp(d / "s1" / "results.json"));
  const std::string name = changed["rows"][0]["run_name"];
  changed["rows"][0]["rmse"] = changed["rows"][0]["rmse"].get<double>() + 0.25;
  fs::create_directories(d / "changed");
  std::ofstream(d / "changed" / "results.json") << changed.dump();
  const Result c = run(d, "",
                       "merge " + (d / "s1").string() + " " + (d / "changed").string() + " --out " +
                           (d / "bad").string() + db);
  EXPECT_EQ(c.code, 2) << c.err;
  EXPECT_NE(c.err.find(name), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("rmse"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(d / "bad" / "results.json"));
}

// LPT on Graham's (1969) example: {5, 4, 3, 3, 3} over 2 shards. Largest first gives 5+3 and
// 4+3+3 (8 and 10; ties go to the lower shard), 10/9 of the optimum 9, within LPT's 4/3 bound.
TEST(ShardPlan, LargestFirstOnGrahamsExample) {
  std::vector<aoeval::PointCost> points;
  int i = 0;
  for (double ms : {3.0, 5.0, 3.0, 4.0, 3.0})
    points.push_back({"p" + std::to_string(i++), ms, "default"});
  const aoeval::ShardPlan plan = aoeval::plan_shards(points, 2);
  EXPECT_EQ(plan.shard_ms, (std::vector<double>{8.0, 10.0}));
  EXPECT_EQ(plan.shard_of, (std::vector<int>{1, 0, 0, 1, 1}));
  EXPECT_DOUBLE_EQ(plan.planned_ratio(), 10.0 / 9.0);
  const fs::path d = aoeval::testutil::test_temp_dir("cluster");
  fs::create_directories(d);
  aoeval::write_shard_plan((d / "plan.json").string(), plan);
  const aoeval::ShardPlan back = aoeval::read_shard_plan((d / "plan.json").string());
  EXPECT_EQ(back.shard_of, plan.shard_of);
  std::vector<std::string> names = {"p0", "p1", "p2", "p3", "p4"};
  size_t total = 0;
  for (int s = 0; s < 2; ++s) total += aoeval::planned_shard(back, names, s, 2, "plan.json").size();
  EXPECT_EQ(total, names.size());
  EXPECT_THROW(aoeval::planned_shard(back, names, 0, 3, "plan.json"), aoeval::InputError);
  names.push_back("p5");
  EXPECT_THROW(aoeval::planned_shard(back, names, 0, 2, "plan.json"), aoeval::InputError);
}

// A point's cost counts its precompute (prepare(): vertex-baked's bake) beside its frames: the
// median of its own run name's history, or for a run name never seen the estimator's precompute
// per unit of work times the point's work (here 4x the rays: 4x the bake and the frames). The
// Slurm shards of the paper suite differed by 2.2x while the plan ignored the bake.
TEST(ShardPlan, CostCountsThePrecompute) {
  const aoeval::EstimatorInfo& baked = aoeval::find_estimator("vertex-baked");
  aoeval::ResultRow row;
  row.run_name = "vertex-baked/rays:128";
  row.estimator = baked.name;
  row.params = {{"rays", 128}};
  row.width = row.height = 100;
  row.time_ms_median = 2.0;
  row.precompute_ms = 1000.0;
  const aoeval::CostModel model({row});
  aoeval::SweepPoint point;
  point.estimator = &baked;
  point.width = point.height = 100;
  point.name = row.run_name;
  point.overrides = {{"rays", 128}};
  const aoeval::TimingSpec timing{1, 5};
  const double scoring_ms = aoeval::kScoringNsPerPixel * 1e4 * 1e-6;
  const aoeval::PointCost seen = model.estimate(point, timing);
  EXPECT_EQ(seen.source, "history");
  EXPECT_DOUBLE_EQ(seen.ms, 6 * 2.0 + 1000.0 + scoring_ms);
  point.name = "vertex-baked/rays:512";
  point.overrides = {{"rays", 512}};
  const aoeval::PointCost scaled = model.estimate(point, timing);
  EXPECT_EQ(scaled.source, "estimator");
  EXPECT_NEAR(scaled.ms, 6 * 8.0 + 4000.0 + scoring_ms, 1e-9);
}

}  // namespace
