// Tests of the point record (point_record.h) and its frames and images in the SQLite history
// (results_store.h): a record read back is the record stored, frames.csv written from the store
// is byte-equal to the one written from evaluation's frames, re-recording a point replaces its
// frames, and a history without the tables reads as none.
#include "harness/results/point_record.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "harness/results/metric_table.h"
#include "harness/results/results_store.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

std::string fresh_db(const std::string& name) {
  const fs::path dir = testutil::test_temp_dir("point_record") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return (dir / "results.sqlite").string();
}

// Frames as evaluation writes them (frames.cpp): frame, time_ms,
// disoccluded_pixels, then the image keys against the matched reference and true AO.
std::vector<nlohmann::json> evaluation_frames(int n, double scale) {
  std::vector<nlohmann::json> frames;
  for (int k = 0; k < n; ++k) {
    nlohmann::json f = {
        {"frame", k}, {"time_ms", 0.1 * k + 1.0 / 3}, {"disoccluded_pixels", 7 * k}};
    for (const auto& key : metric_keys_of(MetricFamily::image)) {
      f[key] = scale * (k + 1) / 3.0;
      f["true_" + key] = scale * (k + 2) / 7.0;
    }
    f["pixels"] = 19200u;
    f["true_pixels"] = 19100u;
    if (k == 1) f["psnr"] = nullptr;  // identical images: +infinity
    frames.push_back(f);
  }
  return frames;
}

ResultRow sequence_row(const std::string& run_id) {
  ResultRow r;
  r.run_id = run_id;
  r.run_name = "raytraced/scene:bunny/view:orbit/160x120";
  r.estimator = "raytraced";
  r.scene = "bunny";
  r.view = "orbit";
  r.width = 160;
  r.height = 120;
  r.estimate_file = "estimates/x.exr";
  return r;
}

TEST(PointRecord, FrameRowRoundTripAndColumns) {
  const auto frames = evaluation_frames(3, 0.01);
  const auto typed = frame_rows(frames);
  ASSERT_EQ(typed.size(), 3u);
  EXPECT_EQ(typed[2].disoccluded_pixels, 14);
  EXPECT_TRUE(typed[1].metrics.at("psnr").is_null());
  EXPECT_EQ(flatten(typed), frames);
  EXPECT_EQ(frames_csv(flatten(typed)), frames_csv(frames));
  EXPECT_EQ(frame_columns().front(), "frame");
  EXPECT_EQ(frame_columns().size(), 3 + 2 * metric_keys_of(MetricFamily::image).size());
}

TEST(PointRecord, BadFrameIsRefusedNamingTheKey) {
  EXPECT_THROW(frame_row({{"time_ms", 1.0}}), InputError);
  try {
    frame_row({{"frame", 0}, {"rmse", "x"}}, "f[0]");
    FAIL() << "a string metric was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f[0].rmse: not a number (\"x\")");
  }
}

TEST(PointRecord, StoredFramesAndImagesReadBackAndExportTheSameFramesCsv) {
  const std::string path = fresh_db("round_trip");
  const auto frames = evaluation_frames(5, 0.02);
  PointRecord rec{.row = sequence_row("run-1"),
                  .frames = frame_rows(frames),
                  .images = {{"estimate", "estimates/x.exr"},
                             {frame_image_role(4, "estimate"), "sequences/x/frame_0004.exr"}}};
  {
    SqliteStore store(path);
    store.add(rec);
  }
  SqliteStore store(path, SqliteStore::Mode::read_only);
  const auto back = store.frames_of("run-1", rec.row.run_name);
  ASSERT_EQ(back.size(), 5u);
  EXPECT_EQ(flatten(back), frames);
  EXPECT_EQ(frames_csv(flatten(back)), frames_csv(frames));
  EXPECT_EQ(store.images_of("run-1", rec.row.run_name), rec.images);
  EXPECT_EQ(rec.images[1].role, "frame 0004 estimate");
  EXPECT_TRUE(store.frames_of("run-2", rec.row.run_name).empty());
  ASSERT_EQ(store.all_rows().size(), 1u);
}

TEST(PointRecord, RecordingAgainReplacesFramesAndARowAloneKeepsThem) {
  const std::string path = fresh_db("replace");
  SqliteStore store(path);
  PointRecord rec{
      .row = sequence_row("run-1"), .frames = frame_rows(evaluation_frames(6, 0.01)), .images = {}};
  store.add(rec);
  rec.frames = frame_rows(evaluation_frames(2, 0.05));
  store.add(rec);
  auto back = store.frames_of("run-1", rec.row.run_name);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_DOUBLE_EQ(back[0].metrics.at("rmse").get<double>(), 0.05 / 3);
  store.add(rec.row);  // resume's repair: the row only
  EXPECT_EQ(store.frames_of("run-1", rec.row.run_name).size(), 2u);
  EXPECT_EQ(store.all_rows().size(), 1u);
}

TEST(PointRecord, AHistoryWithoutTheTablesHasNoFrames) {
  const std::string path = fresh_db("old_file");
  {
    SqliteStore store(path);
    store.add(PointRecord{
        .row = sequence_row("run-1"), .frames = frame_rows(evaluation_frames(2, 1)), .images = {}});
  }
  {  // a file of an earlier build: no frames or images table
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DROP TABLE frames; DROP TABLE images", nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  {
    SqliteStore reader(path, SqliteStore::Mode::read_only);
    EXPECT_TRUE(reader.frames_of("run-1", sequence_row("").run_name).empty());
    EXPECT_TRUE(reader.images_of("run-1", sequence_row("").run_name).empty());
    EXPECT_EQ(reader.all_rows().size(), 1u);
  }
  SqliteStore writer(path);  // opening for writing adds them
  writer.add(PointRecord{
      .row = sequence_row("run-2"), .frames = frame_rows(evaluation_frames(3, 1)), .images = {}});
  EXPECT_EQ(writer.frames_of("run-2", sequence_row("").run_name).size(), 3u);
}

}  // namespace
}  // namespace aoeval
