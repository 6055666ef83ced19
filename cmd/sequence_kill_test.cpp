// Issue 29's must-show 5: a sequence sweep SIGKILLed at 10 random moments and resumed with
// --resume holds every sequence row exactly once (results.json, results.csv, SQLite, one run id),
// each with its complete frames.csv, manifest and kept frames, and the same values as a run that
// was never interrupted; its page has every row's sequence section and every row's references.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "cmd/fault_injection_util.h"
#include "harness/results/results_store.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::csv_run_names;
using aoeval::cli_test::KillCount;
using aoeval::cli_test::slurp;
using aoeval::cli_test::sqlite_strings;
using aoeval::cli_test::sweep_killed_and_resumed;

constexpr int kFrames = 8;
// 48 points: a launch is killed once 0 or 1 new rows exist plus up to 60 ms, so it adds a few
// rows at most; with 20 points a sweep made faster (issue 42: scoring on the background lane, no
// warm-up for CPU estimators) finished on its own after 9 kills. 48 leave room for 10 kills at
// several times that speed.
constexpr size_t kPoints = 48;

// A box sliding across a floor under a camera that pans: every frame disoccludes floor behind the
// box. 32x24 pixels, 8 frames, 16-spp references: a point takes tens of milliseconds, so kills land
// in every phase of a sequence point (its frames, its references, its kept files, the commit).
void write_inputs(const fs::path& d) {
  std::ofstream(d / "slide.json") << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.5, 0.5, 0.5]}}],
    "views": [{"name": "slide", "eye": [0, 1.2, 1.6], "target": [0, 0.2, 0], "fov_y_deg": 50,
               "width": 32, "height": 24,
               "sequence": {"frames": 8, "fps": 30,
                 "camera": [{"frame": 7, "eye": [0.4, 1.2, 1.6], "target": [0.1, 0.2, 0]}],
                 "objects": {"box": [{"frame": 0, "translate": [-0.4, 0, 0]},
                                     {"frame": 7, "translate": [0.4, 0, 0]}]}}}]})";
  const nlohmann::json spec = {
      {"name", "sequence-kill"},
      {"scenes", {(d / "slide.json").string()}},
      {"views", {"slide"}},
      {"reference", {{"spp", 16}, {"sampler", "sobol"}}},
      {"timing", {{"warmup", 0}, {"repetitions", 1}}},
      {"runs",
       {{{"estimator", "constant"},
         {"grid", {{"value", {{"range", {0.1, 0.9, 44}}, {"scale", "lin"}}}}}},
        {{"estimator", "raytraced"}, {"grid", {{"rays", {1, 2, 3, 4}}}}}}}};
  std::ofstream(d / "spec.json") << spec.dump(2);
}

nlohmann::json rows_by_name(const fs::path& out) {
  nlohmann::json by = nlohmann::json::object();
  // Parsed into a named value: iterating a member of a temporary would read freed memory.
  const nlohmann::json results = nlohmann::json::parse(slurp(out / "results.json"));
  for (const auto& r : results["rows"]) by[r["run_name"].get<std::string>()] = r;
  return by;
}

// frames.csv without its time column (timings differ between runs; everything else must not).
std::vector<std::string> frames_without_time(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell, kept;
    for (int i = 0; std::getline(cells, cell, ','); ++i)
      if (i != 1) kept += cell + ",";  // columns: frame, time_ms, disoccluded_pixels, metrics...
    lines.push_back(kept);
  }
  return lines;
}

fs::path point_folder(const fs::path& out, const std::string& run_name) {
  return fs::path(aoeval::frames_csv_path(out.string(), run_name)).parent_path();
}

bool is_measured_column(const std::string& key) {
  return key.rfind("time_ms", 0) == 0 || key == "precompute_ms" || key == "timestamp" ||
         key == "run_id" || key == "machine" || key == "timing_source";
}

TEST(SequenceKill, TenRandomSigkillsThenResumeEqualAnUninterruptedRun) {
  const fs::path d = aoeval::testutil::test_temp_dir("sequence_kill");
  write_inputs(d);
  const std::string spec = (d / "spec.json").string();

  // The uninterrupted run, with a cache of its own: its references are computed, as the killed
  // run's are.
  const fs::path whole = d / "whole";
  const auto clean = aoeval::cli_test::run_aoeval(
      "AOEVAL_CACHE=" + (d / "cache-whole").string() + " ",
      "sweep " + spec + " --out " + whole.string() + " --db " + (d / "whole.sqlite").string(), d);
  ASSERT_EQ(clean.code, 0) << clean.err;

  const fs::path out = d / "out", db = d / "r.sqlite";
  const std::string cache = (d / "cache").string();
  std::mt19937 rng(29);
  // Kill once 0 or 1 new rows exist, after a random 0-60 ms more: the first point of a launch also
  // pays the process start, the scene and the references' cache misses.
  KillCount count;
  ASSERT_NO_FATAL_FAILURE(sweep_killed_and_resumed("sequence kill", spec, out, db, d, cache, rng,
                                                   {.max_kills = 10,
                                                    .max_launches = 40,
                                                    .max_wait_rows = 1,
                                                    .max_delay_us = 60000,
                                                    .polls = 5000},
                                                   &count));
  EXPECT_GE(count.kills, 10);

  // Every sequence row once, in every store, under one run id.
  const nlohmann::json got = rows_by_name(out), want = rows_by_name(whole);
  ASSERT_EQ(want.size(), kPoints);
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "results.json"))["rows"].size(), kPoints);
  std::set<std::string> names;
  for (const auto& [name, row] : want.items()) names.insert(name);
  std::set<std::string> got_names;
  for (const auto& [name, row] : got.items()) got_names.insert(name);
  EXPECT_EQ(got_names, names);
  const auto csv = csv_run_names(out / "results.csv");
  EXPECT_EQ(csv.size(), kPoints);
  EXPECT_EQ(std::set<std::string>(csv.begin(), csv.end()), names);
  const auto db_names = sqlite_strings(db, "SELECT run_name FROM results");
  EXPECT_EQ(db_names.size(), kPoints) << "rows lost or duplicated in SQLite";
  EXPECT_EQ(std::set<std::string>(db_names.begin(), db_names.end()), names);
  EXPECT_EQ(sqlite_strings(db, "SELECT DISTINCT run_id FROM results").size(), 1u);
  // Every point's frames in SQLite, committed with its row (issue 46): all 8 of each point, no
  // point's frames twice, and the kept frames' images by role.
  const auto with_frames = sqlite_strings(
      db, "SELECT run_name FROM frames GROUP BY run_name HAVING count(*) = " +
              std::to_string(kFrames) + " AND count(DISTINCT frame) = " + std::to_string(kFrames));
  EXPECT_EQ(std::set<std::string>(with_frames.begin(), with_frames.end()), names);
  EXPECT_EQ(sqlite_strings(db, "SELECT frame FROM frames").size(), kPoints * kFrames);
  EXPECT_EQ(sqlite_strings(db, "SELECT path FROM images WHERE role LIKE 'frame % estimate'").size(),
            kPoints * kFrames);

  // The same values as the uninterrupted run: every column but the timings and identities, every
  // line of frames.csv but its times, the same manifest, every kept frame on disk.
  size_t compared = 0;
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    if (!got.contains(name)) continue;
    const nlohmann::json& a = got[name];
    const nlohmann::json& b = want[name];
    EXPECT_EQ(a["status"], "ok");
    EXPECT_EQ(a["seq_frames"], kFrames);
    for (const auto& [key, value] : b.items())
      if (!is_measured_column(key)) {
        EXPECT_EQ(a.value(key, nlohmann::json()), value) << key;
        ++compared;
      }
    const fs::path folder = point_folder(out, name), folder_whole = point_folder(whole, name);
    const auto frames = frames_without_time(folder / "frames.csv");
    EXPECT_EQ(frames.size(), static_cast<size_t>(kFrames + 1)) << "frames.csv incomplete";
    EXPECT_EQ(frames, frames_without_time(folder_whole / "frames.csv"));
    const auto manifest = nlohmann::json::parse(slurp(folder / "sequence.json"));
    EXPECT_EQ(manifest, nlohmann::json::parse(slurp(folder_whole / "sequence.json")));
    ASSERT_EQ(manifest["kept"].size(), static_cast<size_t>(kFrames));
    for (const auto& k : manifest["kept"]) {
      EXPECT_TRUE(fs::exists(out / k["estimate"].get<std::string>())) << k.dump();
      EXPECT_TRUE(fs::exists(out / k["reference"].get<std::string>())) << k.dump();
    }
  }
  std::printf("sequence kill: %zu rows, %zu values equal to the uninterrupted run's\n", got.size(),
              compared);

  // The page: a section per sequence row, and every row's references in the record (the record
  // of rows finished before a kill included).
  const std::string page = slurp(out / "index.html");
  size_t sections = 0;
  for (size_t at = page.find("<section class=\"sequence\" "); at != std::string::npos;
       at = page.find("<section class=\"sequence\" ", at + 1))
    ++sections;
  EXPECT_EQ(sections, kPoints);
  const auto record = nlohmann::json::parse(slurp(out / "suite_record.json"));
  size_t with_reference = 0;
  for (const auto& e : record["entries"])
    with_reference += !e.value("reference_exr", std::string()).empty();
  EXPECT_EQ(with_reference, kPoints) << "rows finished before a kill lost their references";

  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos)
        << "a killed write's temporary is left: " << e.path();
}

}  // namespace
