// Issue 28, through the aoeval binary: what a killed or refused command leaves behind is cleaned,
// a view that shows nothing is a skipped row (not the end of a sweep), a failed --slurm submission
// cancels what it submitted and leaves no folder, and `estimate` says what it did in one line.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

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

Result run(const fs::path& d, const std::string& env, const std::string& args) {
  fs::create_directories(d / "capture");
  return aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " " + env, args,
                                      d / "capture");
}

pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

std::vector<fs::path> temporaries_under(const fs::path& d) {
  std::vector<fs::path> found;
  for (const auto& e : fs::recursive_directory_iterator(d))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) found.push_back(e.path());
  return found;
}

// What a SIGKILL in the middle of `aoeval reference` leaves (a temporary of the cache entry and
// one of the -o file, both of a dead pid) is gone after the next run.
TEST(Leftovers, AKilledReferencesTemporariesAreRemovedByTheNextRun) {
  const fs::path d = aoeval::testutil::test_temp_dir("leftovers");
  const std::string args =
      "reference --scene cornell-box --res 16x16 --spp 4 -o " + (d / "o" / "ref.exr").string();
  ASSERT_EQ(run(d, "", args).code, 0);
  fs::path entry;
  for (const auto& e : fs::recursive_directory_iterator(d / "cache"))
    if (e.path().extension() == ".exr") entry = e.path();
  ASSERT_FALSE(entry.empty());
  fs::remove(entry);  // as if killed while writing it: the entry never appeared
  const std::string pid = std::to_string(dead_pid());
  // Appended, not "." + ...: GCC 12 warns falsely on that (-Wrestrict, PR 105329).
  std::string name(".");
  name.append(entry.stem().string()).append(".tmp-").append(pid).append("-0.exr");
  std::ofstream(entry.parent_path() / name) << "half";
  std::ofstream(d / "o" / (".ref.tmp-" + pid + "-1.exr")) << "half";
  ASSERT_EQ(temporaries_under(d).size(), 2u);
  const Result again = run(d, "", args);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(temporaries_under(d).empty()) << temporaries_under(d).front();
  EXPECT_TRUE(fs::exists(entry));
}

TEST(Leftovers, EstimatePrintsOneLineNamingWhatItDid) {
  const fs::path d = aoeval::testutil::test_temp_dir("leftovers");
  const Result r = run(
      d, "",
      "estimate --estimator constant --scene cornell-box --res 16x12 -o " + (d / "e.exr").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  for (const std::string& s :
       std::vector<std::string>{"constant", "cornell-box/", "16x12", " ms", (d / "e.exr").string()})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << " not in: " << r.out;
}

// A view that looks away from every surface: its point is a skipped row naming scene and view,
// and the sweep's other view is scored.
TEST(Leftovers, AViewCoveringNoPixelIsASkippedRow) {
  const fs::path d = aoeval::testutil::test_temp_dir("leftovers");
  std::ofstream(d / "floor.json")
      << R"({"objects": [{"name": "f", "generator": "plane", "params": {"size": [2, 2]}}],
            "views": [{"name": "main", "eye": [0, 1, 3], "target": [0, 0, 0]},
                      {"name": "sky", "eye": [0, 1, 3], "target": [0, 1, 10]}]})";
  std::ofstream(d / "spec.json") << R"({"name": "sky", "scenes": [")" << (d / "floor.json").string()
                                 << R"("], "views": "all", "res": [16, 16],
      "reference": {"spp": 4}, "timing": {"warmup": 0, "repetitions": 1},
      "runs": [{"estimator": "constant"}]})";
  const Result r = run(d, "",
                       "sweep " + (d / "spec.json").string() + " --out " + (d / "o").string() +
                           " --db " + (d / "r.sqlite").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json rows = nlohmann::json::parse(slurp(d / "o" / "results.json"))["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["status"], "ok");
  const std::string status = rows[1]["status"];
  EXPECT_EQ(status.rfind("skipped: scene floor view sky covers no pixel", 0), 0u) << status;
}

// sbatch accepts the first two submissions and refuses the third: the two jobs are cancelled
// (scancel is called with their ids), the folder is gone, and a retry is not told "already holds
// a run".
TEST(Leftovers, AFailedSlurmSubmissionCancelsItsJobsAndLeavesNoFolder) {
  const fs::path d = aoeval::testutil::test_temp_dir("leftovers");
  const fs::path bin = d / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "sbatch")
      << "#!/bin/sh\nn=$(cat " << (d / "count").string()
      << " 2>/dev/null || echo 0)\nn=$((n + 1))\necho $n > " << (d / "count").string()
      << "\nif [ $n -ge 3 ]; then echo 'sbatch: error: QOSMaxSubmitJobPerUserLimit' "
         ">&2; exit 1; fi\necho \"$((100 + n))\"\n";
  std::ofstream(bin / "scancel") << "#!/bin/sh\necho \"$@\" >> " << (d / "cancelled").string()
                                 << "\n";
  for (const char* f : {"sbatch", "scancel"})
    fs::permissions(bin / f, fs::perms::owner_all, fs::perm_options::add);
  std::ofstream(d / "spec.json") << R"({"name": "s", "scenes": ["cornell-box"], "res": [16, 16],
      "reference": {"spp": 4}, "runs": [{"estimator": "constant"}]})";
  const std::string args = "sweep " + (d / "spec.json").string() + " --slurm --out " +
                           (d / "o").string() + " --db " + (d / "r.sqlite").string();
  const std::string env = "PATH=" + bin.string() + ":/usr/bin:/bin ";
  const Result r = run(d, env, args);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("QOSMaxSubmitJobPerUserLimit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cancelled: job 101, 102"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(d / "cancelled"), "101 102\n");
  EXPECT_FALSE(fs::exists(d / "o"));
  fs::remove(d / "count");
  std::ofstream(d / "count") << "-10\n";  // now it accepts all three
  const Result retry = run(d, env, args);
  EXPECT_EQ(retry.code, 0) << retry.err;
  EXPECT_TRUE(fs::exists(d / "o" / "slurm" / "plan.json"));
}

}  // namespace
