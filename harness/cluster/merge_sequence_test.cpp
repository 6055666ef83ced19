// `aoeval merge` carries whole points (issue 46): a sequence point's frames and kept images reach
// the merged folder and its SQLite store as the shard that measured it stored them, so the
// dashboard sees a merged run's frames as it sees a single run's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "harness/results/results_store.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

Result run(const fs::path& d, const std::string& args) {
  return aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " ", args, d);
}

// Two sequence points (24 frames of rolling-ball/roll at 16x12) and one still point.
std::string write_spec(const fs::path& d) {
  const nlohmann::json spec = {
      {"name", "tiny-seq"},
      {"scenes", {"rolling-ball"}},
      {"views", {"roll", "main"}},
      {"res", {16, 12}},
      {"reference", {{"spp", 8}, {"sampler", "sobol"}}},
      {"timing", {{"warmup", 0}, {"repetitions", 1}}},
      {"runs", {{{"estimator", "constant"}}, {{"estimator", "raytraced"}}}}};
  fs::create_directories(d);
  std::ofstream(d / "tiny-seq.json") << spec.dump(2);
  return (d / "tiny-seq.json").string();
}

// run_name -> run_id of a folder's rows.
std::map<std::string, std::string> run_ids(const fs::path& folder) {
  std::map<std::string, std::string> ids;
  const nlohmann::json doc = nlohmann::json::parse(slurp(folder / "results.json"));
  for (const auto& r : doc["rows"]) ids[r["run_name"].get<std::string>()] = r["run_id"];
  return ids;
}

std::vector<nlohmann::json> flat_frames(aoeval::SqliteStore& store, const std::string& run_id,
                                        const std::string& name) {
  std::vector<nlohmann::json> out;
  for (const auto& f : store.frames_of(run_id, name)) out.push_back(aoeval::flatten(f));
  return out;
}

TEST(Merge, CarriesASequencePointsFramesAndImagesIntoTheStore) {
  const fs::path d = aoeval::testutil::test_temp_dir("merge-seq");
  const std::string spec = write_spec(d);
  for (int i = 0; i < 2; ++i) {
    const std::string s = i == 0 ? "s0" : "s1";
    const Result r = run(d, "sweep " + spec + " --db " + (d / (s + ".sqlite")).string() +
                                " --shard " + std::to_string(i) + "/2 --out " + (d / s).string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  const Result m = run(d, "merge " + (d / "s0").string() + " " + (d / "s1").string() + " --out " +
                              (d / "merged").string() + " --db " + (d / "m.sqlite").string());
  ASSERT_EQ(m.code, 0) << m.err;

  aoeval::SqliteStore merged((d / "m.sqlite").string(), aoeval::SqliteStore::Mode::read_only);
  const auto merged_ids = run_ids(d / "merged");
  ASSERT_EQ(merged_ids.size(), 4u);
  size_t sequences = 0;
  fs::path a_frames_csv;  // one sequence point's, in its shard
  for (int i = 0; i < 2; ++i) {
    const std::string s = i == 0 ? "s0" : "s1";
    aoeval::SqliteStore shard((d / (s + ".sqlite")).string(), aoeval::SqliteStore::Mode::read_only);
    for (const auto& [name, id] : run_ids(d / s)) {
      SCOPED_TRACE(name);
      const auto frames = flat_frames(shard, id, name);
      EXPECT_EQ(flat_frames(merged, merged_ids.at(name), name), frames);
      const auto images = shard.images_of(id, name);
      EXPECT_EQ(merged.images_of(merged_ids.at(name), name), images);
      for (const auto& image : images)
        EXPECT_TRUE(fs::exists(d / "merged" / image.path)) << image.role << " " << image.path;
      if (frames.empty()) continue;
      ++sequences;
      EXPECT_EQ(frames.size(), 24u);
      EXPECT_TRUE(fs::exists(aoeval::frames_csv_path((d / "merged").string(), name)));
      a_frames_csv = aoeval::frames_csv_path((d / s).string(), name);
    }
  }
  EXPECT_EQ(sequences, 2u);

  // A shard that lost a sequence point's frames.csv: exit 2 naming the file, nothing merged.
  ASSERT_TRUE(fs::remove(a_frames_csv)) << a_frames_csv;
  const Result lost =
      run(d, "merge " + (d / "s0").string() + " " + (d / "s1").string() + " --out " +
                 (d / "lost").string() + " --db " + (d / "lost.sqlite").string());
  EXPECT_EQ(lost.code, 2) << lost.err;
  EXPECT_NE(lost.err.find("frames.csv is missing"), std::string::npos) << lost.err;
  EXPECT_FALSE(fs::exists(d / "lost" / "results.json"));
}

}  // namespace
