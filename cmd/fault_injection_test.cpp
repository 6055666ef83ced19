// Fault injection (issue 15): a sweep SIGKILLed at random moments, dozens of times, then resumed,
// must hold exactly one row per point in results.csv, results.json and SQLite under one run id;
// two processes given one --out must not both write it; damaged reference-cache entries are
// recomputed, never served; a damaged results database is rejected without being touched.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <thread>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"
#include "cmd/fault_injection_util.h"

namespace {

namespace fs = std::filesystem;
using aoeval::cli_test::csv_run_names;
using aoeval::cli_test::json_row_count;
using aoeval::cli_test::KillCount;
using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;
using aoeval::cli_test::spawn_aoeval;
using aoeval::cli_test::sqlite_strings;
using aoeval::cli_test::sweep_killed_and_resumed;

constexpr int kPoints = 240;

fs::path temp_dir() {
  return aoeval::testutil::test_temp_dir("faults");
}

// A sweep of cheap points: the constant estimator at kPoints values on a small procedural scene, one
// timed frame each, so a run is many short rows and kills land in every phase of a row's life
// (estimating, scoring, the SQLite commit, the atomic rewrites of CSV and JSON).
std::string write_spec(const fs::path& d) {
  const nlohmann::json spec = {
      {"name", "fault-injection"},
      {"scenes", {"cornell-box"}},
      {"res", {24, 24}},
      {"reference", {{"spp", 16}, {"sampler", "sobol"}}},
      {"runs",
       {{{"estimator", "constant"},
         {"grid", {{"value", {{"range", {0.0, 1.0, kPoints}}, {"scale", "lin"}}}}}}}},
      {"timing", {{"warmup", 0}, {"repetitions", 1}}}};
  std::ofstream(d / "spec.json") << spec.dump(2);
  return (d / "spec.json").string();
}

TEST(FaultInjection, ThirtyRandomSigkillsThenResumeKeepOneRowPerPointAndOneRunId) {
  const fs::path d = temp_dir();
  const std::string spec = write_spec(d), cache = (d / "cache").string();
  const fs::path out = d / "out", db = d / "r.sqlite";
  std::mt19937 rng(20261201);
  // Kill after 0, 1 or 2 new rows (a third of the kills land while the process starts up or
  // computes the reference), then after a random 0-4 ms: anywhere in a row's life (a row takes
  // 1-2 ms here since rows are appended, not rewritten; a longer delay let a launch run so many
  // rows that the 160-point sweep finished after 24 kills). 240 points leave room for the 36 kills
  // at two or three rows a launch, and a slower (loaded) machine only makes launches shorter.
  KillCount count;
  ASSERT_NO_FATAL_FAILURE(sweep_killed_and_resumed("fault injection", spec, out, db, d, cache, rng,
                                                   {.max_kills = 36,
                                                    .max_launches = 1000,
                                                    .max_wait_rows = 2,
                                                    .max_delay_us = 4000,
                                                    .polls = 3000},
                                                   &count));
  EXPECT_GE(count.kills, 30);

  const auto j = nlohmann::json::parse(slurp(out / "results.json"));
  std::set<std::string> json_names;
  for (const auto& row : j["rows"]) json_names.insert(row["run_name"].get<std::string>());
  EXPECT_EQ(j["rows"].size(), static_cast<size_t>(kPoints));
  EXPECT_EQ(json_names.size(), static_cast<size_t>(kPoints));

  const auto csv_names = csv_run_names(out / "results.csv");
  EXPECT_EQ(csv_names.size(), static_cast<size_t>(kPoints));
  EXPECT_EQ(std::set<std::string>(csv_names.begin(), csv_names.end()), json_names);

  const auto db_names = sqlite_strings(db, "SELECT run_name FROM results");
  EXPECT_EQ(db_names.size(), static_cast<size_t>(kPoints)) << "rows lost or duplicated in SQLite";
  EXPECT_EQ(std::set<std::string>(db_names.begin(), db_names.end()), json_names);
  const auto run_ids = sqlite_strings(db, "SELECT DISTINCT run_id FROM results");
  ASSERT_EQ(run_ids.size(), 1u) << "one sweep, one run, however often it was killed";
  EXPECT_EQ(j["context"]["run_id"].get<std::string>(), run_ids[0]);
  std::printf("fault injection: %zu CSV rows, %zu JSON rows, %zu SQLite rows, %zu run id(s)\n",
              csv_names.size(), j["rows"].size(), db_names.size(), run_ids.size());

  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos)
        << "a killed write's temporary is left: " << e.path();
}

TEST(FaultInjection, TwoProcessesIntoOneOutFolderTheSecondIsRefused) {
  const fs::path d = temp_dir();
  const std::string spec = write_spec(d), cache = (d / "cache").string();
  const fs::path out = d / "out";
  const pid_t first = spawn_aoeval(
      {"sweep", spec, "--out", out.string(), "--db", (d / "a.sqlite").string()}, d, cache);
  ASSERT_GT(first, 0);
  for (int i = 0; i < 3000 && json_row_count(out) < 1; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const Result second =
      aoeval::cli_test::run_aoeval("AOEVAL_CACHE=" + cache + " ",
                                   "sweep " + spec + " --out " + out.string() + " --db " +
                                       (d / "b.sqlite").string() + " --resume",
                                   d);
  kill(first, SIGKILL);
  waitpid(first, nullptr, 0);
  EXPECT_EQ(second.code, 2) << second.err;
  EXPECT_NE(second.err.find("another aoeval process"), std::string::npos) << second.err;
  EXPECT_NE(second.err.find(out.string()), std::string::npos) << second.err;
}

// The smaller promises of the same order: a shard without points still writes its (empty)
// results files, an unwritable --db fails before any output folder exists, and --resume repairs a
// CSV that lags one row behind results.json (a kill between the two atomic rewrites).
TEST(FaultInjection, EmptyShardsUnwritableDatabasesAndLaggingCsv) {
  const fs::path d = temp_dir();
  const std::string spec = write_spec(d), cache = (d / "cache").string();
  const std::string env = "AOEVAL_CACHE=" + cache + " ";
  // kPoints (240) points, shard 250/300: none of them.
  const Result empty = aoeval::cli_test::run_aoeval(env,
                                                    "sweep " + spec + " --shard 250/300 --out " +
                                                        (d / "empty").string() + " --db " +
                                                        (d / "r.sqlite").string(),
                                                    d);
  ASSERT_EQ(empty.code, 0) << empty.err;
  EXPECT_TRUE(fs::exists(d / "empty" / "results.csv"));
  EXPECT_EQ(json_row_count(d / "empty"), 0u);
  EXPECT_TRUE(fs::exists(d / "empty" / "results.json"));

  const Result no_db = aoeval::cli_test::run_aoeval(
      env, "sweep " + spec + " --out " + (d / "nodb").string() + " --db /proc/no/r.sqlite", d);
  EXPECT_NE(no_db.code, 0);
  EXPECT_FALSE(fs::exists(d / "nodb")) << "the output folder was made before the database failed";

  const fs::path out = d / "lag";
  const std::string sweep = "sweep " + spec + " --shard 0/60 --out " + out.string() + " --db " +
                            (d / "r.sqlite").string();
  ASSERT_EQ(aoeval::cli_test::run_aoeval(env, sweep, d).code, 0);
  const std::string csv = slurp(out / "results.csv");
  const size_t rows = csv_run_names(out / "results.csv").size();
  ASSERT_EQ(rows, 4u);
  // Drop the last line, as a kill between the JSON and the CSV rewrite would leave it.
  const size_t cut = csv.rfind('\n', csv.size() - 2);
  std::ofstream(out / "results.csv", std::ios::trunc) << csv.substr(0, cut + 1);
  ASSERT_EQ(csv_run_names(out / "results.csv").size(), rows - 1);
  const Result resumed = aoeval::cli_test::run_aoeval(env, sweep + " --resume", d);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(slurp(out / "results.csv"), csv) << "--resume did not rewrite the lagging CSV";
}

// Runs `aoeval reference` into `output` with the given cache; returns stderr.
std::string reference(const fs::path& d, const std::string& cache, const fs::path& output) {
  const Result r = aoeval::cli_test::run_aoeval(
      "AOEVAL_CACHE=" + cache + " ",
      "reference --scene cornell-box --res 24x24 --spp 16 --sampler sobol -o " + output.string(),
      d);
  EXPECT_EQ(r.code, 0) << r.err;
  return r.err;
}

std::vector<float> ao_pixels(const fs::path& exr);

TEST(FaultInjection, DamagedReferenceCacheEntriesAreRecomputedNeverServed) {
  const fs::path d = temp_dir();
  const std::string cache = (d / "cache").string();
  reference(d, cache, d / "first.exr");
  std::vector<fs::path> entries;
  // The entry's lock file (references/cache_lock.h) stays beside it: removing a flock'd file
  // would let a second writer lock a new inode while the first still holds the old one.
  for (const auto& e : fs::directory_iterator(fs::path(cache) / "references"))
    if (e.path().extension() != ".lock") entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 1u);
  const fs::path entry = entries[0];
  const std::string good = slurp(entry);
  EXPECT_NE(reference(d, cache, d / "served.exr").find("served from cache"), std::string::npos);

  const std::map<std::string, std::string> damages = {
      {"truncated", good.substr(0, good.size() / 2)},
      {"another EXR", std::string()},  // written below: a G-buffer of the same size
      {"one byte flipped near the end", [&] {
         std::string s = good;
         s[s.size() - 20] = static_cast<char>(s[s.size() - 20] ^ 0x5a);
         return s;
       }()}};
  for (const auto& [what, bytes] : damages) {
    SCOPED_TRACE(what);
    if (what == "another EXR") {
      const Result g = aoeval::cli_test::run_aoeval(
          "AOEVAL_CACHE=" + cache + " ",
          "gbuffer --scene cornell-box --res 24x24 -o " + (d / "g.exr").string(), d);
      ASSERT_EQ(g.code, 0) << g.err;
      fs::copy_file(d / "g.exr", entry, fs::copy_options::overwrite_existing);
    } else {
      std::ofstream(entry, std::ios::binary | std::ios::trunc) << bytes;
    }
    const std::string err = reference(d, cache, d / "again.exr");
    EXPECT_NE(err.find("reference cache:"), std::string::npos) << err;
    EXPECT_NE(err.find("recomputing"), std::string::npos) << err;
    EXPECT_EQ(err.find("served from cache"), std::string::npos) << err;
    EXPECT_EQ(ao_pixels(d / "again.exr"), ao_pixels(d / "first.exr"));
    // The recomputed entry is whole again and served next time.
    EXPECT_NE(reference(d, cache, d / "third.exr").find("served from cache"), std::string::npos);
  }
}

TEST(FaultInjection, DamagedResultsDatabasesAreRejectedByteIdentical) {
  const fs::path d = temp_dir();
  const std::string spec = write_spec(d), cache = (d / "cache").string();
  const fs::path db = d / "good.sqlite";
  const Result sweep = aoeval::cli_test::run_aoeval(
      "AOEVAL_CACHE=" + cache + " ",
      "sweep " + spec + " --shard 0/60 --out " + (d / "out").string() + " --db " + db.string(), d);
  ASSERT_EQ(sweep.code, 0) << sweep.err;
  const std::string good = slurp(db);
  ASSERT_GT(good.size(), 4096u);
  const std::map<std::string, std::string> damaged = {
      {"truncated.sqlite", good.substr(0, good.size() / 2 + 100)},
      {"zeroed-page.sqlite",
       [&] {
         std::string s = good;
         std::fill(s.begin() + 4096, s.begin() + 8192, '\0');
         return s;
       }()},
      {"random.sqlite", std::string(8192, '\x5a')},
      {"empty.sqlite", std::string()}};
  for (const auto& [name, bytes] : damaged) {
    SCOPED_TRACE(name);
    const fs::path file = d / name;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    const Result r = aoeval::cli_test::run_aoeval(
        "", "dashboard --no-charts --db " + file.string() + " --out " + (d / "dash").string(), d);
    EXPECT_EQ(r.code, 2) << r.err << r.out;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_EQ(slurp(file), bytes) << "the rejected database was modified";
    EXPECT_FALSE(fs::exists(file.string() + "-wal"));
    EXPECT_FALSE(fs::exists(file.string() + "-shm"));
  }
}

}  // namespace

#include <OpenImageIO/imagebuf.h>

namespace {
std::vector<float> ao_pixels(const fs::path& exr) {
  OIIO::ImageBuf image(exr.string());
  image.read(0, 0, true, OIIO::TypeDesc::FLOAT);
  const int ao = image.spec().channelindex("AO");
  std::vector<float> out;
  for (OIIO::ImageBuf::ConstIterator<float> it(image); !it.done(); ++it) out.push_back(it[ao]);
  return out;
}
}  // namespace
