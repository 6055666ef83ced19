// Tests of the results row (result_row.h) and the results store (results_store.h): flat round
// trip, CSV/JSON/Markdown/console writers, the output folder with --resume, and SQLite.
#include "harness/results/results_store.h"
#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "harness/results/machine_class.h"
#include "harness/results/metric_table.h"
#include "harness/results/result_row.h"
#include "harness/results/stage_times.h"

#include <gtest/gtest.h>

#include <sqlite3.h>
#include <chrono>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

namespace aoeval {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = aoeval::testutil::test_temp_dir("store") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

nlohmann::json metrics(double rmse, bool infinite_psnr) {
  nlohmann::json m = {
      {"pixels", 76800u},
      {"rmse", rmse},
      {"mae", rmse * 0.8},
      {"bias", -0.1 * rmse},
      {"max_abs", 0.5},
      {"p95_abs", 0.25},
      {"psnr", infinite_psnr ? nlohmann::json(nullptr) : nlohmann::json(20.0 + rmse)},
      {"ssim", 0.9},
      {"flip_mean", 0.1 / 3},
      {"ref_stderr_rms", 0.001},
      {"rmse_excess", rmse / 7}};
  // Every other image key of the metric table (a metric added there needs no edit here).
  for (const auto& k : metric_keys_of(MetricFamily::image))
    if (!m.contains(k)) m[k] = 0.01 * rmse;
  return m;
}

ResultRow make_row(const std::string& estimator, nlohmann::json params, const std::string& scene,
                   double rmse, const std::string& run_id = "run-1") {
  ResultRow r;
  r.run_id = run_id;
  r.estimator = estimator;
  r.params = std::move(params);
  r.scene = scene;
  r.view = "main";
  r.width = 320;
  r.height = 240;
  r.run_name = estimator + "/" + r.params.dump() + "/scene:" + scene + "/view:main/320x240";
  r.definition = R"({"weighting":"cosine"})";
  r.reference = {{"spp", 256}, {"sampler", "stratified"}, {"seed", 1}};
  r.metrics = metrics(rmse, false);
  r.true_metrics = metrics(rmse / 3, true);
  r.time_ms_median = 1.0 / 3;
  r.time_ms_min = 0.1;
  r.time_ms_max = 12345.678901234567;
  r.repetitions = 5;
  r.time_ms_samples = {0.2, 1.0 / 3, 0.1, 12345.678901234567, 0.5};
  r.precompute_ms = 2.5;
  r.backend = "cpu";
  r.machine = "host (CPU, 2 cores)";
  r.device = "CPU";
  r.git_commit = "0123456789abcdef0123456789abcdef01234567";
  r.aoeval_version = "0.1.0";
  r.estimator_version = "built-in:3f2a91c0b1d2";
  r.timestamp = "2024-05-01T12:00:00Z";
  r.estimate_file = "estimates/" + scene + ".exr";
  return r;
}

void expect_same(const ResultRow& a, const ResultRow& b) {
  EXPECT_EQ(a.run_id, b.run_id);
  EXPECT_EQ(a.run_name, b.run_name);
  EXPECT_EQ(a.estimator, b.estimator);
  EXPECT_EQ(a.params, b.params);
  EXPECT_EQ(a.params.dump(), b.params.dump());
  EXPECT_EQ(a.scene, b.scene);
  EXPECT_EQ(a.view, b.view);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.definition, b.definition);
  EXPECT_EQ(a.reference, b.reference);
  EXPECT_EQ(a.metrics, b.metrics);
  EXPECT_EQ(a.true_metrics, b.true_metrics);
  EXPECT_EQ(a.time_ms_median, b.time_ms_median);
  EXPECT_EQ(a.time_ms_min, b.time_ms_min);
  EXPECT_EQ(a.time_ms_max, b.time_ms_max);
  EXPECT_EQ(a.repetitions, b.repetitions);
  EXPECT_EQ(a.time_ms_samples, b.time_ms_samples);
  EXPECT_EQ(a.pass_ms, b.pass_ms);
  EXPECT_EQ(a.precompute_ms, b.precompute_ms);
  EXPECT_EQ(a.backend, b.backend);
  EXPECT_EQ(a.machine, b.machine);
  EXPECT_EQ(a.device, b.device);
  EXPECT_EQ(a.git_commit, b.git_commit);
  EXPECT_EQ(a.aoeval_version, b.aoeval_version);
  EXPECT_EQ(a.estimator_version, b.estimator_version);
  EXPECT_EQ(a.timestamp, b.timestamp);
  EXPECT_EQ(a.estimate_file, b.estimate_file);
  EXPECT_EQ(a.status, b.status);
}

// RFC 4180 reader: rows of fields.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(std::move(field));
      field.clear();
    } else if (c == '\n') {
      row.push_back(std::move(field));
      field.clear();
      rows.push_back(std::move(row));
      row.clear();
    } else {
      field += c;
    }
  }
  EXPECT_FALSE(quoted) << "unterminated quote";
  EXPECT_TRUE(field.empty() && row.empty()) << "last line not terminated";
  return rows;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t index_of(const std::vector<std::string>& v, const std::string& x) {
  const auto it = std::find(v.begin(), v.end(), x);
  EXPECT_NE(it, v.end()) << x;
  return static_cast<size_t>(it - v.begin());
}

TEST(StageTimes, SumsByStageInFirstUseOrderAndCountsTheEstimatorsShare) {
  StageTimes t;
  t.add("scoring", 2.0);
  t.add(StageTimes::kEstimatorFrames, 6.0);
  t.add("scoring", 1.0);
  t.add(StageTimes::kEstimatorWarmup, 1.0);
  EXPECT_EQ(t.ms("scoring"), 3.0);
  EXPECT_EQ(t.ms("never"), 0.0);
  EXPECT_EQ(t.total_ms(), 10.0);
  EXPECT_EQ(t.estimator_ms(), 7.0);
  EXPECT_EQ(t.to_json(),
            (nlohmann::json{
                {"scoring", 3.0}, {"estimator timed frames", 6.0}, {"estimator warm-up", 1.0}}));
  EXPECT_LT(t.table(20.0).find("scoring"), t.table(20.0).find("estimator timed frames"));
  StageTimes u;
  u.add_all(t);
  u.add_all(t);
  EXPECT_EQ(u.ms("scoring"), 6.0);
  const std::string table = t.table(20.0);
  EXPECT_NE(table.find("other (untimed)"), std::string::npos) << table;
  EXPECT_NE(table.find(" 35.0 %  (estimator share of wall time)"), std::string::npos) << table;
  // A scope adds the time it lived: at least the 2 ms it waited out on the clock it reads, at
  // most the time around it (no bound depends on how fast the machine is).
  using Clock = std::chrono::steady_clock;
  const auto outer = Clock::now();
  {
    const auto timer = u.time("timed scope");
    const auto inner = Clock::now();
    while (Clock::now() - inner < std::chrono::milliseconds(2)) {
    }
  }
  const double around = std::chrono::duration<double, std::milli>(Clock::now() - outer).count();
  EXPECT_GE(u.ms("timed scope"), 2.0);
  EXPECT_LE(u.ms("timed scope"), around);
  EXPECT_TRUE(u.to_json().contains("timed scope"));
}

TEST(ResultRow, FlattenUnflattenRoundTrip) {
  ResultRow r =
      make_row("raytraced", {{"rays", 16}, {"blur", true}, {"R", 0.1}, {"mode", "a,\"b\""}},
               "bunny", 0.0123456789);
  r.pass_ms = {{"horizon_ms", 0.75}, {"blur_ms", 1.0 / 7}};
  r.status = "skipped: no Vulkan device";
  const nlohmann::json flat = flatten(r);
  EXPECT_EQ(flat["rays"], 16);
  EXPECT_EQ(flat["mode"], "a,\"b\"");
  EXPECT_EQ(flat["true_rmse"], r.true_metrics["rmse"]);
  EXPECT_TRUE(flat["true_psnr"].is_null());
  EXPECT_TRUE(flat["params"].is_string());
  EXPECT_EQ(flat["horizon_ms"], 0.75);
  expect_same(unflatten(flat), r);
  // Through JSON text too.
  expect_same(unflatten(nlohmann::json::parse(flat.dump())), r);

  // A skipped row without metrics keeps empty metric objects.
  ResultRow skipped = make_row("hbao", {{"R", 0.5}}, "bunny", 0.1);
  skipped.metrics = nlohmann::json::object();
  skipped.true_metrics = nlohmann::json::object();
  expect_same(unflatten(flatten(skipped)), skipped);
}

TEST(ResultRow, ParameterNamedLikeFixedColumnIsPrefixed) {
  const ResultRow r = make_row("odd", {{"scene", "x"}, {"rmse", 2}, {"k", 1}}, "bunny", 0.2);
  const nlohmann::json flat = flatten(r);
  EXPECT_EQ(flat["param_scene"], "x");
  EXPECT_EQ(flat["param_rmse"], 2);
  EXPECT_EQ(flat["scene"], "bunny");
  expect_same(unflatten(flat), r);
}

TEST(ResultRow, FlatKeysAreTheColumns) {
  ResultRow r = make_row("raytraced", {{"rays", 16}}, "bunny", 0.01);
  r.pass_ms = {{"trace_ms", 3.0}};
  std::vector<std::string> keys;
  const nlohmann::json flat = flatten(r);
  for (const auto& item : flat.items()) keys.push_back(item.key());
  std::vector<std::string> columns;
  // The bent-normal columns (bent_metrics.h) stay blank for an estimator without bent normals, and
  // the sequence columns (scoring/temporal.h) for a still view.
  const std::vector<std::string> blank = {
      "bent_",           "seq_",          "steady_rmse",       "temporal_rmse",
      "converge_frames", "settle_frames", "disocclusion_rmse", "lag_rmse"};
  for (const auto& c : result_columns({r})) {
    bool is_blank = false;
    for (const auto& b : blank) is_blank = is_blank || c.find(b) != std::string::npos;
    if (!is_blank) columns.push_back(c);
  }
  std::sort(keys.begin(), keys.end());
  std::sort(columns.begin(), columns.end());
  EXPECT_EQ(keys, columns);
  r.metrics["bent_angle_mean"] = 3.0;
  EXPECT_EQ(flatten(r)["bent_angle_mean"], 3.0);
  EXPECT_EQ(unflatten(flatten(r)).metrics["bent_angle_mean"], 3.0);
  EXPECT_TRUE(unflatten(flatten(r)).pass_ms.count("bent_angle_mean") == 0);
}

TEST(ResultsCsv, HeaderOrderQuotingAndExactNumbers) {
  ResultRow r = make_row("raytraced", {{"rays", 16}, {"mode", "a,\"b\""}}, "bunny", 0.0123456789);
  r.pass_ms = {{"trace_ms", 0.1 + 0.2}};
  const auto table = parse_csv(results_csv({r}));
  ASSERT_EQ(table.size(), 2u);
  std::vector<std::string> expected = identifying_columns();
  expected.insert(expected.end(), {"mode", "rays"});
  for (const auto& c : measured_columns()) expected.push_back(c);
  expected.push_back("trace_ms");
  EXPECT_EQ(table[0], expected);
  EXPECT_EQ(expected[0], "run_id");
  EXPECT_EQ(expected[10], "params");
  const auto& header = table[0];
  const auto& cells = table[1];
  ASSERT_EQ(cells.size(), header.size());
  EXPECT_EQ(cells[index_of(header, "mode")], "a,\"b\"");
  EXPECT_EQ(nlohmann::json::parse(cells[index_of(header, "params")]), r.params);
  EXPECT_EQ(cells[index_of(header, "rays")], "16");
  EXPECT_EQ(cells[index_of(header, "true_psnr")], "inf");
  EXPECT_EQ(std::strtod(cells[index_of(header, "rmse")].c_str(), nullptr), 0.0123456789);
  EXPECT_EQ(std::strtod(cells[index_of(header, "time_ms_median")].c_str(), nullptr), 1.0 / 3);
  EXPECT_EQ(std::strtod(cells[index_of(header, "trace_ms")].c_str(), nullptr), 0.1 + 0.2);
  EXPECT_EQ(std::strtod(cells[index_of(header, "flip_mean")].c_str(), nullptr), 0.1 / 3);
  EXPECT_EQ(cells[index_of(header, "width")], "320");
  // The raw text quotes per RFC 4180.
  EXPECT_NE(results_csv({r}).find(",\"a,\"\"b\"\"\","), std::string::npos);
}

TEST(ResultsCsv, TwoEstimatorsLeaveBlanks) {
  ResultRow a = make_row("hbao", {{"R", 0.2}, {"Nd", 8}}, "bunny", 0.01);
  a.pass_ms = {{"horizon_ms", 1.5}};
  const ResultRow b = make_row("raytraced", {{"rays", 32}}, "bunny", 0.02);
  const auto table = parse_csv(results_csv({a, b}));
  ASSERT_EQ(table.size(), 3u);
  const auto& h = table[0];
  // Parameters by first appearance (a's in column order, then b's), passes last.
  EXPECT_EQ(index_of(h, "Nd"), 11u);
  EXPECT_EQ(index_of(h, "R"), 12u);
  EXPECT_EQ(index_of(h, "rays"), 13u);
  EXPECT_EQ(index_of(h, "pixels"), 14u);
  EXPECT_EQ(h.back(), "horizon_ms");
  EXPECT_EQ(table[1][index_of(h, "R")], "0.2");
  EXPECT_EQ(table[1][index_of(h, "rays")], "");
  EXPECT_EQ(table[2][index_of(h, "R")], "");
  EXPECT_EQ(table[2][index_of(h, "Nd")], "");
  EXPECT_EQ(table[2][index_of(h, "rays")], "32");
  EXPECT_EQ(table[2][index_of(h, "horizon_ms")], "");
  for (const auto& line : table) EXPECT_EQ(line.size(), h.size());
}

TEST(ResultsCsv, SkippedRowsHaveBlankTimesNotZero) {
  ResultRow skipped = make_row("hbao", {{"R", 0.2}}, "bunny", 0.01);
  skipped.status = "skipped: no Vulkan device";
  skipped.set_times({});
  skipped.precompute_ms = 0.0;
  const ResultRow ran = make_row("hbao", {{"R", 0.4}}, "bunny", 0.01);
  const auto table = parse_csv(results_csv({skipped, ran}));
  ASSERT_EQ(table.size(), 3u);
  for (const char* column : {"time_ms_median", "time_ms_min", "time_ms_max", "precompute_ms"}) {
    EXPECT_EQ(table[1][index_of(table[0], column)], "") << column;
    EXPECT_NE(table[2][index_of(table[0], column)], "") << column;
  }
  const nlohmann::json j = nlohmann::json::parse(results_json({skipped}, make_run_context("t")));
  for (const char* key : {"time_ms_median", "time_ms_min", "time_ms_max", "precompute_ms"})
    EXPECT_TRUE(j["rows"][0][key].is_null()) << key;
  EXPECT_EQ(unflatten(j["rows"][0]).time_ms_median, 0.0);  // read back as "no time"
}

TEST(ResultsJson, SchemaVersionContextAndRows) {
  RunContext context = make_run_context("sweep test");
  const ResultRow r = make_row("hbao", {{"R", 0.2}}, "bunny", 0.01);
  const nlohmann::json j = nlohmann::json::parse(results_json({r}, context));
  EXPECT_EQ(j["schema_version"], kResultsSchemaVersion);
  EXPECT_EQ(j["context"]["command"], "sweep test");
  EXPECT_EQ(j["context"]["run_id"], context.run_id);
  for (const char* key :
       {"machine", "device", "embree_version", "git_commit", "aoeval_version", "started"}) {
    EXPECT_TRUE(j["context"].contains(key)) << key;
  }
  ASSERT_EQ(j["rows"].size(), 1u);
  expect_same(unflatten(j["rows"][0]), r);
}

TEST(RunContextTest, Fields) {
  const RunContext c = make_run_context("run default");
  EXPECT_EQ(c.command, "run default");
  EXPECT_EQ(c.run_id.size(), std::string("20240501T123456Z-3f9a1c").size()) << c.run_id;
  EXPECT_EQ(c.started.size(), std::string("2024-05-01T12:34:56Z").size()) << c.started;
  EXPECT_EQ(c.started.back(), 'Z');
  EXPECT_NE(c.machine.find("cores"), std::string::npos);
  EXPECT_FALSE(c.device.empty());
  EXPECT_TRUE(c.git_commit == "unknown" || c.git_commit.size() == 40) << c.git_commit;
  EXPECT_NE(make_run_context("x").run_id, make_run_context("x").run_id);
  const RunContext back = run_context_from_json(to_json(c));
  EXPECT_EQ(back.run_id, c.run_id);
  EXPECT_EQ(back.embree_version, c.embree_version);
}

TEST(ResultsFolderTest, ResumeLoadsRowsAndAddsWithoutDuplicates) {
  const fs::path dir = fresh_dir("out") / "nested";
  std::vector<ResultRow> rows;
  for (int i = 0; i < 4; ++i)
    rows.push_back(make_row("hbao", {{"R", 0.1 * (i + 1)}}, "bunny", 0.01 * i));
  {
    ResultsFolder folder(dir.string(), make_run_context("sweep a"));
    EXPECT_TRUE(folder.load_existing().empty());
    for (int i = 0; i < 3; ++i) folder.add(rows[i]);
    EXPECT_EQ(folder.rows().size(), 3u);
  }
  ResultsFolder again(dir.string(), make_run_context("sweep a"));
  const std::vector<std::string> names = again.load_existing();
  ASSERT_EQ(names.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(names[i], rows[i].run_name);
  for (int i = 0; i < 3; ++i) expect_same(again.rows()[i], rows[i]);
  again.add(rows[3]);
  again.add(rows[1]);  // the same run name again replaces, never duplicates
  ASSERT_EQ(again.rows().size(), 4u);
  const auto table = parse_csv(read(dir / "results.csv"));
  ASSERT_EQ(table.size(), 5u);
  std::set<std::string> seen;
  for (size_t i = 1; i < table.size(); ++i) seen.insert(table[i][1]);
  EXPECT_EQ(seen.size(), 4u);
  EXPECT_EQ(nlohmann::json::parse(read(dir / "results.json"))["rows"].size(), 4u);
}

TEST(ResultsFolderTest, FilesAreWholeAfterEveryAdd) {
  const fs::path dir = fresh_dir("out");
  ResultsFolder folder(dir.string(), make_run_context("sweep b"));
  for (int n = 1; n <= 5; ++n) {
    // Alternate estimators so the header grows and older rows get rewritten with blanks.
    folder.add(n % 2 ? make_row("hbao", {{"R", 0.1 * n}}, "bunny", 0.01)
                     : make_row("raytraced", {{"rays", n}}, "dragon", 0.02));
    const auto table = parse_csv(read(dir / "results.csv"));
    ASSERT_EQ(table.size(), static_cast<size_t>(n) + 1);
    for (const auto& line : table) EXPECT_EQ(line.size(), table[0].size());
    EXPECT_EQ(nlohmann::json::parse(read(dir / "results.json"))["rows"].size(),
              static_cast<size_t>(n));
    // No temporary left beside them.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 2u);
  }
}

TEST(ResultsFolderTest, NewerSchemaIsRefused) {
  const fs::path dir = fresh_dir("out");
  std::ofstream(dir / "results.json") << R"({"schema_version": 99, "context": {}, "rows": []})";
  ResultsFolder folder(dir.string(), make_run_context("sweep c"));
  EXPECT_THROW(folder.load_existing(), std::runtime_error);
}

int user_version(const std::string& path) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &s, nullptr);
  const int v = sqlite3_step(s) == SQLITE_ROW ? sqlite3_column_int(s, 0) : -1;
  sqlite3_finalize(s);
  sqlite3_close(db);
  return v;
}

TEST(SqliteStoreTest, TwoRunsReopenAndRead) {
  const std::string path = (fresh_dir("db") / "out" / "results.sqlite").string();
  RunContext c1 = make_run_context("sweep one"), c2 = make_run_context("sweep two");
  c1.started = "2024-01-01T00:00:00Z";
  c2.started = "2024-01-02T00:00:00Z";
  std::vector<ResultRow> one, two;
  one.push_back(make_row("hbao", {{"R", 0.2}, {"blur", true}}, "bunny", 0.01, c1.run_id));
  one.back().pass_ms = {{"horizon_ms", 0.5}};
  one.push_back(make_row("hbao", {{"R", 0.5}, {"blur", false}}, "bunny", 0.02, c1.run_id));
  two.push_back(
      make_row("raytraced", {{"rays", 64}, {"mode", "a,'b\""}}, "dragon", 0.03, c2.run_id));
  {
    SqliteStore store(path);
    store.add_run(c1);
    for (const auto& r : one) store.add(r);
    store.add_run(c2);
    for (const auto& r : two) store.add(r);
  }
  SqliteStore store(path);
  EXPECT_EQ(store.run_ids(), (std::vector<std::string>{c1.run_id, c2.run_id}));
  EXPECT_EQ(store.runs()[1].command, "sweep two");
  EXPECT_EQ(store.runs()[1].embree_version, c2.embree_version);
  const auto all = store.all_rows();
  ASSERT_EQ(all.size(), 3u);
  expect_same(all[0], one[0]);
  expect_same(all[1], one[1]);
  expect_same(all[2], two[0]);
  const auto of_two = store.rows_of_run(c2.run_id);
  ASSERT_EQ(of_two.size(), 1u);
  expect_same(of_two[0], two[0]);
  EXPECT_TRUE(store.rows_of_run("no such run").empty());
  EXPECT_EQ(user_version(path), kResultsSchemaVersion);
}

TEST(SqliteStoreTest, NewParameterAddsColumn) {
  const std::string path = (fresh_dir("db") / "results.sqlite").string();
  SqliteStore store(path);
  store.add(make_row("hbao", {{"R", 0.2}}, "bunny", 0.01));
  auto columns = store.columns();
  EXPECT_NE(std::find(columns.begin(), columns.end(), "R"), columns.end());
  EXPECT_EQ(std::find(columns.begin(), columns.end(), "Nd"), columns.end());
  EXPECT_EQ(std::find(columns.begin(), columns.end(), "param_scene"), columns.end());
  store.add(make_row("hbao", {{"R", 0.2}, {"Nd", 8}, {"scene", "y"}}, "bunny", 0.01));
  columns = store.columns();
  EXPECT_NE(std::find(columns.begin(), columns.end(), "Nd"), columns.end());
  EXPECT_NE(std::find(columns.begin(), columns.end(), "param_scene"), columns.end());
  EXPECT_EQ(store.all_rows().size(), 2u);
  EXPECT_EQ(store.all_rows()[0].params, (nlohmann::json{{"R", 0.2}}));
}

// Files written before the estimator_version column (results.json, results.sqlite) still load,
// the version "" (unknown); a new row in the old database adds the column.
TEST(SqliteStoreTest, FilesWithoutTheEstimatorVersionColumnStillLoad) {
  nlohmann::json flat = flatten(make_row("hbao", {{"R", 0.2}}, "bunny", 0.01));
  ASSERT_TRUE(flat.contains("estimator_version"));
  flat.erase("estimator_version");
  EXPECT_EQ(unflatten(flat).estimator_version, "");

  const std::string path = (fresh_dir("db_old") / "results.sqlite").string();
  { SqliteStore(path).add(make_row("hbao", {{"R", 0.2}}, "bunny", 0.01)); }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, "ALTER TABLE results DROP COLUMN estimator_version", nullptr, nullptr,
                         nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(db);
  sqlite3_close(db);
  SqliteStore store(path);
  auto columns = store.columns();
  EXPECT_EQ(std::find(columns.begin(), columns.end(), "estimator_version"), columns.end());
  ASSERT_EQ(store.all_rows().size(), 1u);
  EXPECT_EQ(store.all_rows()[0].estimator_version, "");
  store.add(make_row("hbao", {{"R", 0.5}}, "bunny", 0.01));
  ASSERT_EQ(store.all_rows().size(), 2u);
  EXPECT_EQ(store.all_rows()[1].estimator_version, "built-in:3f2a91c0b1d2");
}

// One machine's CPU rows and lavapipe rows are one class (their times compare, as the leaderboard
// shows them together); another node of the same kind too; a real GPU is a class of its own.
TEST(MachineClass, TheCpuAndLavapipeOfOneMachineAreOneClass) {
  ResultRow cpu = make_row("gtao-cpu", {}, "bunny", 0.01);
  cpu.machine = "node1 (AMD EPYC 7B13, 2 cores)";
  cpu.device = "AMD EPYC 7B13";
  ResultRow lavapipe = cpu;
  lavapipe.backend = "vulkan";
  lavapipe.device = "llvmpipe (LLVM 15.0.6, 256 bits) [cpu, Mesa 22.3.6]";
  ResultRow other_node = cpu;
  other_node.machine = "node2 (AMD EPYC 7B13, 2 cores)";
  ResultRow gpu = lavapipe;
  gpu.device = "NVIDIA H100 80GB HBM3";
  EXPECT_EQ(machine_classes({cpu, lavapipe, other_node}).size(), 1u);
  EXPECT_EQ(machine_class(cpu), "AMD EPYC 7B13, 2 cores | CPU");
  EXPECT_EQ(machine_class(gpu), "AMD EPYC 7B13, 2 cores | NVIDIA H100 80GB HBM3");
  EXPECT_EQ(machine_classes({cpu, gpu}).size(), 2u);
}

TEST(SqliteStoreTest, NewerSchemaThrows) {
  const std::string path = (fresh_dir("db") / "results.sqlite").string();
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  EXPECT_THROW(SqliteStore store(path), std::runtime_error);
  EXPECT_EQ(user_version(path), 99);
}

TEST(SqliteStoreTest, UnopenablePathThrows) {
  const fs::path dir = fresh_dir("db");
  fs::create_directories(dir / "is_a_directory.sqlite");
  EXPECT_THROW(SqliteStore store((dir / "is_a_directory.sqlite").string()), std::runtime_error);
}

TEST(SqliteStoreTest, TwoStoresOnOneFileBothAdd) {
  const std::string path = (fresh_dir("db") / "results.sqlite").string();
  SqliteStore a(path), b(path);
  a.add(make_row("hbao", {{"R", 0.1}}, "bunny", 0.01, "run-a"));
  b.add(make_row("raytraced", {{"rays", 4}}, "bunny", 0.01, "run-b"));
  a.add(make_row("hbao", {{"R", 0.3}, {"Nn", 2}}, "bunny", 0.01, "run-a"));
  EXPECT_EQ(b.all_rows().size(), 3u);
  // Concurrently, as two shards would, each adding new parameter columns.
  auto shard = [&](SqliteStore& store, const std::string& run, const std::string& param) {
    for (int i = 0; i < 20; ++i) {
      store.add(make_row(run, {{param + std::to_string(i % 3), i}}, "bunny", 0.01 * i, run));
    }
  };
  std::thread ta(shard, std::ref(a), "shard-1", "x"), tb(shard, std::ref(b), "shard-2", "y");
  ta.join();
  tb.join();
  EXPECT_EQ(a.all_rows().size(), 43u);
  EXPECT_EQ(b.rows_of_run("shard-1").size(), 20u);
  EXPECT_EQ(SqliteStore(path).run_ids().size(), 4u);
  EXPECT_EQ(user_version(path), 1);
}

TEST(Tables, MarkdownAndConsole) {
  const std::vector<ResultRow> rows = {make_row("hbao", {{"R", 0.2}}, "bunny", 0.0123456),
                                       make_row("raytraced|x", {{"rays", 8}}, "dragon", 0.5)};
  const std::string md = markdown_table(rows, {"estimator", "scene", "R", "rmse", "true_psnr"});
  EXPECT_NE(md.find("| estimator | scene | R | rmse | true_psnr |\n|---|---|---:|---:|---:|\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| hbao | bunny | 0.2 | 0.01235 | inf |"), std::string::npos) << md;
  EXPECT_NE(md.find("| raytraced\\|x | dragon |  | 0.5 | inf |"), std::string::npos) << md;

  const std::string console = console_table(rows, {"estimator", "rmse", "time_ms_max"});
  std::istringstream lines(console);
  std::vector<std::string> l;
  for (std::string s; std::getline(lines, s);) l.push_back(s);
  ASSERT_EQ(l.size(), 4u) << console;
  EXPECT_EQ(l[0], "estimator       rmse  time_ms_max");
  EXPECT_EQ(l[1], "-----------  -------  -----------");
  EXPECT_EQ(l[2], "hbao         0.01235        12346");
  EXPECT_EQ(l[3], "raytraced|x      0.5        12346");
}

// A skipped row prints its name and its reason (it once printed as a blank line).
TEST(Tables, ConsoleNamesASkippedRow) {
  std::vector<ResultRow> rows = {make_row("hbao", {{"R", 0.2}}, "bunny", 0.0123456)};
  ResultRow skipped;
  skipped.estimator = "my-ssao";
  skipped.run_name = "my-ssao/scene:bunny/view:main/64x48";
  skipped.status = "skipped: exit 3: out of memory";
  rows.push_back(skipped);
  const std::string console = console_table(rows, {"run_name", "rmse"});
  EXPECT_NE(console.find("\nmy-ssao/scene:bunny/view:main/64x48  skipped: exit 3: out of memory\n"),
            std::string::npos)
      << console;
  EXPECT_EQ(console.find("\n\n"), std::string::npos) << console;
}

}  // namespace
}  // namespace aoeval

namespace aoeval {
namespace {

std::string unflatten_error(const nlohmann::json& flat) {
  try {
    unflatten(flat, "f.json: rows[2]");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Issue 28: one validator for every row read from disk, naming the file, the row and the column.
TEST(ResultRow, RowsReadFromDiskAreCheckedNamingRowAndColumn) {
  EXPECT_EQ(unflatten_error(1), "f.json: rows[2]: expected a results row (a JSON object), got 1");
  EXPECT_EQ(unflatten_error(nlohmann::json::object()),
            "f.json: rows[2].run_name: required field is missing");
  nlohmann::json flat = flatten(make_row("hbao", {{"R", 0.5}}, "bunny", 0.1));
  EXPECT_EQ(unflatten_error(flat), "");
  auto with = [&](const char* key, nlohmann::json value) {
    nlohmann::json f = flat;
    f[key] = std::move(value);
    return unflatten_error(f);
  };
  EXPECT_EQ(with("run_name", ""), "f.json: rows[2].run_name: must not be empty");
  EXPECT_EQ(with("width", "x"), "f.json: rows[2].width: expected an integer, got \"x\"");
  EXPECT_EQ(with("rmse", "x"), "f.json: rows[2].rmse: expected a number or null, got \"x\"");
  EXPECT_EQ(with("params", "[1]"), "f.json: rows[2].params: expected an object, got [1]");
  EXPECT_EQ(with("time_ms_median", -1), "f.json: rows[2].time_ms_median: value -1 is out of range");
  EXPECT_EQ(with("status", 3), "f.json: rows[2].status: expected a string, got 3");
}

TEST(ResultsFolderTest, ARunNameTwiceIsRefused) {
  const fs::path dir = fresh_dir("out");
  const nlohmann::json row = flatten(make_row("hbao", {{"R", 0.5}}, "bunny", 0.1));
  std::ofstream(dir / "results.json")
      << nlohmann::json{{"schema_version", 1}, {"rows", {row, row}}}.dump();
  try {
    read_results_file((dir / "results.json").string());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rows[1].run_name"), std::string::npos) << e.what();
  }
}

// The writers refuse another application's database before writing a byte (the dashboard's
// read-only check, the same words), and leave no file where they created one and failed.
TEST(SqliteStoreTest, AnotherApplicationsDatabaseIsRefusedAndLeftUnchanged) {
  const fs::path dir = fresh_dir("db");
  const std::string path = (dir / "notes.sqlite").string();
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "CREATE TABLE notes (text TEXT); INSERT INTO notes VALUES ('mine')", nullptr,
               nullptr, nullptr);
  sqlite3_close(db);
  const std::string before = read(path);
  try {
    SqliteStore store(path);
    FAIL() << "opened";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--db " + path + ": not an aoeval results database (it holds other tables: notes)");
  }
  EXPECT_EQ(read(path), before);
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);  // no -wal or -shm beside it
  std::ofstream(dir / "text.sqlite") << "not a database at all, but long enough to be read as one";
  EXPECT_THROW(SqliteStore((dir / "text.sqlite").string()), InputError);
}

// Issue 48: views whose names read alike once sanitised ("a<b", "a>b") got one estimate file and
// one reference file between them. The stem keeps the readable part and adds the name's hash.
TEST(FileStem, UniquePerRunNameAndReadable) {
  const std::string lt = "raytraced/rays:16/scene:bunny/view:a<b/64x48";
  const std::string gt = "raytraced/rays:16/scene:bunny/view:a>b/64x48";
  const std::string colon = "raytraced/rays:16/scene:bunny/view:a:b/64x48";
  const std::string dash = "raytraced/rays:16/scene:bunny/view:a-b/64x48";
  EXPECT_EQ(file_stem_for(lt).rfind("raytraced__rays-16__scene-bunny__view-a_b__64x48_", 0), 0u)
      << file_stem_for(lt);
  EXPECT_EQ(file_stem_for(lt), file_stem_for(lt));  // stable
  const std::set<std::string> stems = {file_stem_for(lt), file_stem_for(gt), file_stem_for(colon),
                                       file_stem_for(dash)};
  EXPECT_EQ(stems.size(), 4u);
  for (const auto& s : stems)
    EXPECT_EQ(
        s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-"),
        std::string::npos)
        << s;
  EXPECT_NO_THROW(
      check_file_stems({lt, gt, colon, dash, lt}, "spec.json"));  // a repeat is one point
}

// Two names that read alike and whose 32-bit hashes collide (found by search: the hash is
// FNV-1a, base/hash.h): refused, naming both, rather than one file overwriting the other.
TEST(FileStem, ACollisionIsRefused) {
  const std::string a = "raytraced/scene:box/view:<<<?\"<\"\"/8x8";
  const std::string b = "raytraced/scene:box/view:><>*?**>/8x8";
  ASSERT_EQ(file_stem_for(a), file_stem_for(b));
  try {
    check_file_stems({a, b}, "spec.json");
    ADD_FAILURE() << "a shared file name was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("spec.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(a), std::string::npos) << what;
    EXPECT_NE(what.find(b), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace aoeval
