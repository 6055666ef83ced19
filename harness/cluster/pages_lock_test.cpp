// `run` and `merge` write their pages from the store while they still hold their output folder
// (issue 46), as sweep_pages_test checks for a sweep: a second lock taken inside the page writer
// must fail, and the page writer's path is what the runner returns.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/testing/scoped_env.h"
#include "base/testing/test_temp_dir.h"
#include "harness/cluster/merge.h"
#include "harness/results/output_lock.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/suite_runner.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

// A page writer that records whether the folder was still held and what the store gave it.
struct LockProbe {
  bool called = false, locked = false;
  size_t entries = 0;
  PageWriter writer() {
    return [this](const std::string& dir, const std::string& database) {
      called = true;
      try {
        OutputFolderLock second(dir);
      } catch (const InputError&) {
        locked = true;
      }
      entries = read_stored_run(dir, database).report.entries.size();
      return dir + "/the page";
    };
  }
};

fs::path small_suite(const fs::path& d) {
  const nlohmann::json suite = nlohmann::json::array(
      {{{"name", "pages-lock"},
        {"scenes", {"rolling-ball"}},
        {"views", {"main"}},
        {"reference", {{"spp", 8}, {"sampler", "sobol"}}},
        {"timing", {{"warmup", 0}, {"repetitions", 1}}},
        {"runs", {{{"estimator", "constant"}}, {{"estimator", "raytraced"}}}}}});
  std::ofstream(d / "suite.json") << suite.dump(1);
  return d / "suite.json";
}

// A run of the small suite into `out` with its own store (`shard`: "" or "I/N").
SuiteRunOptions suite_run(const fs::path& suite, const fs::path& out, const std::string& shard) {
  SuiteRunOptions o;
  o.suite = suite.string();
  o.shard = shard;
  o.out_dir = out.string();
  o.database = out.string() + ".sqlite";
  return o;
}

// What the probe saw, for the command `what` whose page is `page` in `out`.
void expect_written_under_lock(const LockProbe& probe, const std::string& page,
                               const std::string& out, const char* what) {
  ASSERT_TRUE(probe.called) << what << " wrote no pages";
  EXPECT_TRUE(probe.locked) << what << " wrote its pages after it let its folder go";
  EXPECT_EQ(probe.entries, 2u) << what;
  EXPECT_EQ(page, out + "/the page") << what;
}

TEST(PagesUnderLock, RunWritesItsPagesWhileItHoldsItsFolder) {
  const fs::path d = testutil::test_temp_dir("pages_lock_run");
  const testutil::ScopedEnv cache("AOEVAL_CACHE", (d / "cache").string());
  LockProbe probe;
  SuiteRunOptions o = suite_run(small_suite(d), d / "out", "");
  o.pages = probe.writer();
  expect_written_under_lock(probe, run_suite(o).page, o.out_dir, "run");
}

TEST(PagesUnderLock, MergeWritesItsPagesWhileItHoldsItsFolder) {
  const fs::path d = testutil::test_temp_dir("pages_lock_merge");
  const testutil::ScopedEnv cache("AOEVAL_CACHE", (d / "cache").string());
  const fs::path suite = small_suite(d);
  MergeOptions m;
  size_t rows = 0;
  for (const char* shard : {"0/2", "1/2"}) {
    const SuiteRunOptions o = suite_run(suite, d / ("shard" + std::string(1, shard[0])), shard);
    rows += run_suite(o).rows;
    m.dirs.push_back(o.out_dir);
  }
  ASSERT_EQ(rows, 2u);  // the two shards hold the suite's two points between them
  LockProbe probe;
  m.out = (d / "merged").string();
  m.database = (d / "merged.sqlite").string();
  m.pages = probe.writer();
  expect_written_under_lock(probe, merge_results(m).page, m.out, "merge");
}

}  // namespace
}  // namespace aoeval
