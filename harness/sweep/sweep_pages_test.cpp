// A sweep's pages are written from the store while the sweep still holds its folder (issue 46):
// the PageWriter runs with the folder locked, and the run reader (suite_record_io.h) finds every
// point's kept files by role in the SQLite store, a sequence point's manifest and frames.csv
// among them, at the paths the runner wrote.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/testing/scoped_env.h"
#include "base/testing/test_temp_dir.h"
#include "harness/results/output_lock.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/sweep_runner.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

TEST(SweepPages, AreWrittenFromTheStoreWhileTheSweepHoldsItsFolder) {
  const fs::path d = testutil::test_temp_dir("sweep_pages");
  const testutil::ScopedEnv cache("AOEVAL_CACHE", (d / "cache").string());
  const nlohmann::json spec = {{"name", "pages"},
                               {"scenes", {"rolling-ball"}},
                               {"views", {"roll", "main"}},
                               {"res", {16, 12}},
                               {"reference", {{"spp", 8}, {"sampler", "sobol"}}},
                               {"timing", {{"warmup", 0}, {"repetitions", 1}}},
                               {"runs", {{{"estimator", "constant"}}}}};
  std::ofstream(d / "pages.json") << spec.dump(1);
  SweepOptions o;
  o.spec_path = (d / "pages.json").string();
  o.out_dir = (d / "out").string();
  o.database = (d / "db.sqlite").string();
  bool locked = false;
  StoredRun stored;
  o.pages = [&](const std::string& dir, const std::string& database) {
    try {
      OutputFolderLock second(dir);  // the sweep's lock must still be held
    } catch (const InputError&) {
      locked = true;
    }
    stored = read_stored_run(dir, database);
    return std::string("the page");
  };
  std::string page;
  ASSERT_EQ(run_sweep(o, nullptr, &page), 0);
  EXPECT_EQ(page, "the page");
  EXPECT_TRUE(locked) << "the pages were written after the sweep let its folder go";
  ASSERT_EQ(stored.report.entries.size(), 2u);
  int sequences = 0;
  for (const SuiteReportEntry& e : stored.report.entries) {
    SCOPED_TRACE(e.row.run_name);
    EXPECT_EQ(e.image("estimate"), e.row.estimate_file);
    EXPECT_EQ(e.reference_exr, e.image("reference"));
    for (const char* role : {"estimate", "reference", "true reference"}) {
      EXPECT_FALSE(e.image(role).empty()) << role;
      EXPECT_TRUE(fs::exists(d / "out" / e.image(role))) << role;
    }
    if (e.row.view != "roll") {
      EXPECT_EQ(e.image("sequence"), "");
      continue;
    }
    ++sequences;
    const fs::path folder = fs::path("sequences") / file_stem_for(e.row.run_name);
    EXPECT_EQ(e.image("sequence"), (folder / "sequence.json").string());
    EXPECT_EQ(e.image("frames"), (folder / "frames.csv").string());
    EXPECT_TRUE(fs::exists(d / "out" / e.image("sequence")));
    EXPECT_TRUE(fs::exists(d / "out" / e.image("frames")));
  }
  EXPECT_EQ(sequences, 1);
}

}  // namespace
}  // namespace aoeval
