// The command line as users and scripts see it (CONTRACT §2): exit codes, one-line errors that name
// the file and the field, no partial outputs, and the corpus listing.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include <OpenImageIO/imagebuf.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"

namespace {

namespace fs = std::filesystem;

using aoeval::cli_test::Result;
using aoeval::cli_test::slurp;

fs::path temp_dir() {
  return aoeval::testutil::test_temp_dir("cli");
}

Result run_with_env(const std::string& env, const std::string& args) {
  return aoeval::cli_test::run_aoeval(env, args, temp_dir());
}

Result run(const std::string& args) {
  return run_with_env("", args);
}

size_t lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

const char* kView = R"("views": [{"name": "main", "eye": [0, 1, 3], "target": [0, 0, 0]}])";

// Each bad scene: exit 2, one line on stderr naming the file and the field, no output file.
void expect_bad_scene(const std::string& file, const std::string& text, const std::string& field) {
  fs::path d = temp_dir();
  std::ofstream(d / file) << text;
  const fs::path out = d / "g.exr";
  fs::remove(out);
  Result r = run("gbuffer --scene " + (d / file).string() + " -o " + out.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(field), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(d))
    EXPECT_EQ(e.path().filename().string().find(".g.tmp"), std::string::npos)
        << "leftover temporary";
}

TEST(Cli, MisspelledKey) {
  expect_bad_scene(
      "typo.json",
      std::string(R"({"objects": [{"name": "p", "generator": "plane", "rol": "ground"}], )") +
          kView + "}",
      "objects[0].rol");
}

TEST(Cli, MissingMesh) {
  expect_bad_scene(
      "missing.json",
      std::string(R"({"objects": [{"name": "m", "mesh": "absent.off"}], )") + kView + "}",
      "objects[0].mesh");
}

TEST(Cli, NaNMesh) {
  fs::path d = temp_dir();
  std::ofstream(d / "nan.off") << "OFF\n3 1 0\n0 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n";
  expect_bad_scene("nanmesh.json",
                   std::string(R"({"objects": [{"name": "m", "mesh": "nan.off"}], )") + kView + "}",
                   "objects[0].mesh");
}

TEST(Cli, ZeroWidthView) {
  expect_bad_scene("zero.json", R"({"objects": [{"name": "p", "generator": "plane"}],
      "views": [{"name": "v", "eye": [0, 1, 3], "target": [0, 0, 0], "width": 0, "height": 10}]})",
                   "views[0].width");
}

TEST(Cli, BadUsageExitsTwo) {
  const std::string never = (temp_dir() / "never.exr").string();
  EXPECT_EQ(run("gbuffer --scene no-such-scene -o " + never).code, 2);
  EXPECT_EQ(run("gbuffer --scene bunny --res 0x10 -o " + never).code, 2);
  EXPECT_EQ(run("gbuffer --scene bunny --view nope -o " + never).code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("run --suite nope").code, 2);
  EXPECT_FALSE(fs::exists(never));
  EXPECT_EQ(run("--help").code, 0);
  EXPECT_EQ(run("gbuffer --help").code, 0);
}

TEST(Cli, GbufferWritesTheContractChannels) {
  const fs::path out = temp_dir() / "g.exr";
  Result r = run("gbuffer --scene cornell-box --res 64x48 -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  OIIO::ImageBuf image(out.string());
  ASSERT_TRUE(image.read());
  const auto& spec = image.spec();
  EXPECT_EQ(spec.width, 64);
  EXPECT_EQ(spec.height, 48);
  for (const char* c :
       {"A", "Z", "P.X", "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "Ng.X", "Ng.Y", "Ng.Z", "objectId"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.get_string_attribute("aoeval:scene"), "cornell-box");
  EXPECT_FALSE(spec.get_string_attribute("aoeval:view").empty());
  EXPECT_FALSE(spec.get_string_attribute("aoeval:version").empty());
}

TEST(Cli, ScenesListHasTheWholeCorpusAndABigEcosystem) {
  Result r = run("scenes list --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "quiet when stderr is not a terminal: " << r.err;
  for (const char* n : {"sphere-uniform", "sphere-uniform-dense", "tree-apple", "tree-poplar",
                        "tree-ground", "grass-field", "ecosystem", "cornell-box", "room", "bunny",
                        "dragon", "armadillo", "elephant"})
    EXPECT_NE(r.out.find(std::string("\"") + n + "\""), std::string::npos) << n;
  const auto pos = r.out.find("\"ecosystem\"");
  ASSERT_NE(pos, std::string::npos);
  const auto tri = r.out.find("\"triangles\":", pos);
  ASSERT_NE(tri, std::string::npos);
  EXPECT_GE(std::stoll(r.out.substr(tri + 12)), 5000000ll);
}

TEST(Cli, ReferenceIsCachedAndCarriesItsHeader) {
  const fs::path d = temp_dir();
  fs::remove_all(d / "cache");
  const std::string env = "AOEVAL_CACHE=" + (d / "cache").string() + " ";
  const std::string args = "reference --scene cornell-box --res 32x32 --spp 16 --sampler sobol -o ";
  Result first = run_with_env(env, args + (d / "a.exr").string());
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_EQ(first.err.find("from cache"), std::string::npos) << first.err;
  Result second = run_with_env(env, args + (d / "b.exr").string());
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(second.err.find("served from cache"), std::string::npos) << second.err;
  EXPECT_EQ(slurp(d / "a.exr"), slurp(d / "b.exr"));
  Result uncached = run_with_env(env, args + (d / "c.exr").string() + " --no-cache");
  ASSERT_EQ(uncached.code, 0) << uncached.err;
  EXPECT_EQ(uncached.err.find("from cache"), std::string::npos);

  OIIO::ImageBuf image((d / "a.exr").string());
  ASSERT_TRUE(image.read());
  const auto& spec = image.spec();
  for (const char* c : {"AO", "AO_stderr", "bent.X", "bent.Y", "bent.Z", "A"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  for (const char* a :
       {"aoeval:scene", "aoeval:view", "aoeval:definition", "aoeval:spp", "aoeval:sampler",
        "aoeval:seed", "aoeval:estimator", "aoeval:params", "aoeval:version"})
    EXPECT_FALSE(spec.get_string_attribute(a).empty()) << a;
  EXPECT_EQ(spec.get_string_attribute("aoeval:sampler"), "sobol");
  EXPECT_EQ(spec.get_string_attribute("aoeval:spp"), "16");
}

// CONTRACT §3 power:K: the reference computes it and says so in its header; a bad K is exit 2 on
// one line that quotes it.
TEST(Cli, ReferenceTakesPowerFalloffAndRefusesABadK) {
  const fs::path d = temp_dir();
  const std::string out = (d / "power.exr").string();
  Result ok =
      run("reference --scene cornell-box --res 8x8 --spp 4 --no-cache --dmax 1 "
          "--falloff power:3 -o " +
          out);
  ASSERT_EQ(ok.code, 0) << ok.err;
  OIIO::ImageBuf image(out);
  ASSERT_TRUE(image.read());
  EXPECT_NE(image.spec().get_string_attribute("aoeval:definition").find("\"power:3\""),
            std::string::npos)
      << image.spec().get_string_attribute("aoeval:definition");
  const std::string never = (d / "never-power.exr").string();
  for (const char* k : {"power:0", "power:-2", "power:nan", "power:inf", "power:abc",
                        "power:", "power:3x", "power:1e999"}) {
    Result r = run("reference --scene cornell-box --res 8x8 --no-cache --dmax 1 --falloff " +
                   std::string(k) + " -o " + never);
    EXPECT_EQ(r.code, 2) << k << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << k << ": " << r.err;
    EXPECT_NE(r.err.find(std::string("'") + k + "'"), std::string::npos) << k << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(never));
}

// `--frame` that is no frame number is a short parse error (CLI11's NonNegativeNumber printed
// "not in range 0 to" a 310-digit number), and `--json` naming a folder is exit 2 naming it (it
// was exit 1 naming this process's temporary).
TEST(Cli, AFrameThatIsNoNumberAndAJsonThatIsAFolderExitTwo) {
  const std::string out = (temp_dir() / "never.exr").string();
  for (const char* command : {"gbuffer", "reference"})
    for (const char* bad : {"two", "-1", "1.5"}) {
      const Result r = run(std::string(command) + " --scene cornell-box --res 8x8 --frame " + bad +
                           " -o " + out);
      EXPECT_EQ(r.code, 2) << command << " " << bad << ": " << r.err;
      EXPECT_EQ(lines(r.err), 1u) << r.err;
      EXPECT_NE(r.err.find("--frame: must be a frame number (a non-negative integer), got '" +
                           std::string(bad) + "'"),
                std::string::npos)
          << r.err;
      EXPECT_LT(r.err.size(), 200u) << r.err;
    }
  EXPECT_FALSE(fs::exists(out));
  const fs::path folder = temp_dir() / "json-folder";
  fs::create_directories(folder);
  const std::string ao = (temp_dir() / "ao.exr").string();
  ASSERT_EQ(run("estimate --estimator constant --scene cornell-box --res 8x8 -o " + ao).code, 0);
  const Result r = run("compare " + ao + " " + ao + " --json " + folder.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(folder.string() + ": is a folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(".tmp-"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(folder));
}

TEST(Cli, ReferenceBadOptionsExitTwo) {
  const std::string out = (temp_dir() / "never.exr").string();
  for (const char* bad : {"--falloff linear", "--sampler halton", "--weighting area", "--dmax -1",
                          "--spp 0", "--normal bent", "--target-stderr 0.01 --max-spp 8"}) {
    Result r = run("reference --scene cornell-box --res 8x8 --no-cache " + std::string(bad) +
                   " -o " + out);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << bad << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, UnknownSetKeyExitsTwoNamingTheKey) {
  const fs::path out = temp_dir() / "e.exr";
  Result r = run("estimate --estimator raytraced --scene cornell-box --res 16x16 --set rayz=4 -o " +
                 out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("rayz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rays"), std::string::npos) << "lists the known keys: " << r.err;
  EXPECT_FALSE(fs::exists(out));
  r = run("estimate --estimator raytraced --scene cornell-box --res 16x16 --set rays=0 -o " +
          out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("[1, 65536]"), std::string::npos) << r.err;
  EXPECT_EQ(run("estimate --estimator nope --scene cornell-box -o " + out.string()).code, 2);
  EXPECT_EQ(run("estimators show nope").code, 2);
}

// No Vulkan driver at all (the loader finds no ICD): a Vulkan estimator is skipped with the reason
// and exit 1, leaves no file, and a sweep with it and a CPU estimator still scores the CPU one.
TEST(Cli, VulkanEstimatorWithoutADeviceIsSkippedWithTheReason) {
  const std::string no_driver =
      "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json ";
  const fs::path out = temp_dir() / "hbao.exr";
  Result r = run_with_env(no_driver,
                          "estimate --estimator hbao-split --scene cornell-box --res "
                          "32x32 -o " +
                              out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("skipped: no Vulkan device ("), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));

  const fs::path d = temp_dir();
  std::ofstream(d / "mixed.json") << R"({"name": "mixed", "scenes": ["cornell-box"],
    "res": [24, 24], "reference": {"spp": 4, "sampler": "sobol"},
    "timing": {"warmup": 0, "repetitions": 1},
    "runs": [{"estimator": "hbao-split"}, {"estimator": "constant"}]})";
  fs::remove_all(d / "sweep");
  r = run_with_env(no_driver, "sweep " + (d / "mixed.json").string() + " --out " +
                                  (d / "sweep").string() + " --db " + (d / "r.sqlite").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = nlohmann::json::parse(slurp(d / "sweep" / "results.json"))["rows"];
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    if (row["estimator"] == "hbao-split") {
      EXPECT_EQ(row["status"].get<std::string>().rfind("skipped: no Vulkan device (", 0), 0u);
      // Never timed: blank times, not 0 ms (issue 30).
      for (const char* key : {"time_ms_median", "time_ms_min", "time_ms_max", "precompute_ms"})
        EXPECT_TRUE(row[key].is_null()) << key << " " << row[key];
    } else {
      EXPECT_EQ(row["estimator"], "constant");
      EXPECT_EQ(row["status"], "ok");
      EXPECT_TRUE(row["rmse"].is_number());
    }
  }
}

// Issue 16: a sweep says where its wall time went, on stderr and in results.json's context; the
// stages add up to no more than the wall time and the estimator's own stages are there.
TEST(Cli, SweepReportsItsTimeByStage) {
  const fs::path d = temp_dir();
  std::ofstream(d / "stages.json") << R"({"name": "stages", "scenes": ["cornell-box"],
    "res": [24, 24], "reference": {"spp": 4, "sampler": "sobol"},
    "timing": {"warmup": 1, "repetitions": 2},
    "runs": [{"estimator": "constant"}, {"estimator": "raytraced", "grid": {"rays": [4]}}]})";
  const Result r = run_with_env("AOEVAL_CACHE=" + (d / "cache").string() + " ",
                                "sweep " + (d / "stages.json").string() + " --out " +
                                    (d / "out").string() + " --db " + (d / "r.sqlite").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("sweep stages: time by stage"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(estimator share of wall time)"), std::string::npos) << r.err;
  const auto stages =
      nlohmann::json::parse(slurp(d / "out" / "results.json"))["context"]["stages_ms"];
  ASSERT_TRUE(stages.is_object()) << stages;
  // The foreground stages add up to at most the wall time; scoring and the results files ran on
  // the background lane, beside the next point's estimator, and are marked overlapped.
  double sum = 0.0;
  const std::string overlapped = " (overlapped)";
  for (const auto& [stage, ms] : stages.items())
    if (stage != "wall" && !stage.ends_with(overlapped)) sum += ms.get<double>();
  EXPECT_LE(sum, stages["wall"].get<double>());
  for (const std::string stage :
       {"estimator precompute", "estimator warm-up", "estimator timed frames", "reference compute",
        "waiting for background work", "scoring (overlapped)", "results CSV + JSON (overlapped)"})
    EXPECT_TRUE(stages.contains(stage)) << stage << " missing from " << stages;
  EXPECT_GT(stages["estimator timed frames"].get<double>(), 0.0);
}

TEST(Cli, EstimateCompareAndMaps) {
  const fs::path d = temp_dir();
  const std::string env = "AOEVAL_CACHE=" + (d / "cache").string() + " ";
  ASSERT_EQ(run_with_env(env, "reference --scene cornell-box --res 48x48 --spp 64 -o " +
                                  (d / "ref.exr").string())
                .code,
            0);
  Result e = run("estimate --estimator raytraced --scene cornell-box --res 48x48 --set rays=4 -o " +
                 (d / "est.exr").string());
  ASSERT_EQ(e.code, 0) << e.err;
  Result c = run("compare " + (d / "ref.exr").string() + " " + (d / "est.exr").string() +
                 " --errmap " + (d / "abs.png").string() + " --signed " +
                 (d / "signed.png").string() + " --mosaic " + (d / "mosaic.png").string());
  ASSERT_EQ(c.code, 0) << c.err;
  const auto metrics = nlohmann::json::parse(c.out);
  for (const char* k : {"pixels", "rmse", "mae", "bias", "max_abs", "p95_abs", "psnr", "ssim",
                        "flip_mean", "ref_stderr_rms", "rmse_excess"})
    EXPECT_TRUE(metrics.contains(k)) << k;
  EXPECT_GT(metrics["rmse"].get<double>(), metrics["ref_stderr_rms"].get<double>())
      << "4 rays are noisier than the 64-spp reference";
  for (const char* f : {"abs.png", "signed.png", "mosaic.png"}) EXPECT_TRUE(fs::exists(d / f)) << f;
  // Comparing a reference with itself: zero error, ssim 1.
  Result same = run("compare " + (d / "ref.exr").string() + " " + (d / "ref.exr").string());
  const auto z = nlohmann::json::parse(same.out);
  EXPECT_EQ(z["rmse"].get<double>(), 0.0);
  EXPECT_EQ(z["ssim"].get<double>(), 1.0);
  EXPECT_EQ(run("compare " + (d / "ref.exr").string() + " " + (d / "missing.exr").string()).code,
            2);
}

// A sweep of 16 points on a slow-to-trace scene, so that SIGINT lands in the middle of it.
std::string write_sweep_spec(const fs::path& d) {
  const nlohmann::json spec = {
      {"name", "cli-sweep"},
      {"scenes", {"tree-apple"}},
      {"res", {40, 40}},
      {"reference", {{"spp", 32}, {"sampler", "sobol"}}},
      {"runs",
       {{{"estimator", "raytraced"},
         {"grid", {{"rays", {1, 2, 3, 4, 5, 6, 7, 8}}, {"sampler", {"random", "stratified"}}}}}}},
      {"timing", {{"warmup", 0}, {"repetitions", 8}}}};
  std::ofstream(d / "spec.json") << spec.dump(2);
  return (d / "spec.json").string();
}

std::vector<nlohmann::json> csv_rows(const fs::path& csv) {
  // results.json holds the same rows as results.csv; read it for simplicity.
  const auto j = nlohmann::json::parse(slurp(csv.parent_path() / "results.json"));
  return j["rows"].get<std::vector<nlohmann::json>>();
}

size_t csv_line_count(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n;
}

TEST(Cli, SweepInterruptedBySigintResumesWithOneRowPerPoint) {
  const fs::path d = temp_dir();
  fs::remove_all(d / "out");
  const std::string spec = write_sweep_spec(d);
  const std::string out = (d / "out").string(), db = (d / "r.sqlite").string();
  std::vector<std::string> args = {AOEVAL_BINARY, "sweep", spec, "--out", out, "--db", db};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, (d / "sweep.out").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, (d / "sweep.err").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, AOEVAL_BINARY, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // Wait for the second row, then interrupt.
  const fs::path csv = fs::path(out) / "results.csv";
  for (int i = 0; i < 6000 && !(fs::exists(csv) && csv_line_count(csv) >= 3); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  const int code = WEXITSTATUS(status);
  const size_t after_interrupt = csv_rows(csv).size();
  EXPECT_EQ(code, 130) << slurp(d / "sweep.err");
  EXPECT_LT(after_interrupt, 16u) << "the interrupt came after the sweep finished";
  EXPECT_GE(after_interrupt, 2u);

  Result again = run("sweep " + spec + " --out " + out + " --db " + db);
  EXPECT_EQ(again.code, 2) << "an existing folder needs --resume";
  Result resumed = run("sweep " + spec + " --out " + out + " --db " + db + " --resume");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const auto rows = csv_rows(csv);
  std::set<std::string> names;
  for (const auto& r : rows) names.insert(r["run_name"].get<std::string>());
  EXPECT_EQ(rows.size(), 16u);
  EXPECT_EQ(names.size(), 16u);
  EXPECT_EQ(csv_line_count(csv), 17u);
}

TEST(Cli, TwoShardsEqualTheUnshardedSweep) {
  const fs::path d = temp_dir();
  fs::remove_all(d / "all");
  fs::remove_all(d / "s0");
  fs::remove_all(d / "s1");
  const std::string spec = write_sweep_spec(d), db = (d / "r.sqlite").string();
  const Result unsharded = run("sweep " + spec + " --out " + (d / "all").string() + " --db " + db);
  ASSERT_EQ(unsharded.code, 0) << unsharded.err;
  // The sweep's page, as a suite's: its path is the last line on stdout (README, "The suite
  // report"); the leaderboard, the chart and viewers on the Pareto-front points are in it.
  const std::string page = (d / "all" / "index.html").string();
  EXPECT_TRUE(unsharded.out.ends_with("\n" + page + "\n")) << unsharded.out;
  const std::string html = slurp(page);
  for (const char* expected : {"id=\"leaderboard\"", "<img class=\"chart\"",
                               "class=\"aoeval-viewer\"", "aoeval: cli-sweep sweep"})
    EXPECT_NE(html.find(expected), std::string::npos) << expected;
  EXPECT_TRUE(fs::exists(d / "all" / "viewer" / "viewer.js"));
  ASSERT_EQ(run("sweep " + spec + " --shard 0/2 --out " + (d / "s0").string() + " --db " + db).code,
            0);
  ASSERT_EQ(run("sweep " + spec + " --shard 1/2 --out " + (d / "s1").string() + " --db " + db).code,
            0);
  std::map<std::string, double> all, shards;
  for (const auto& r : csv_rows(d / "all" / "results.csv"))
    all[r["run_name"]] = r["rmse"].get<double>();
  for (const char* s : {"s0", "s1"})
    for (const auto& r : csv_rows(d / s / "results.csv")) {
      EXPECT_FALSE(shards.count(r["run_name"])) << "shards overlap";
      shards[r["run_name"]] = r["rmse"].get<double>();
    }
  EXPECT_EQ(all.size(), 16u);
  EXPECT_EQ(shards, all) << "same points and, being deterministic, the same errors";
  // Merging the shards writes the sweep's page too (the references travel with the shards).
  fs::remove_all(d / "merged");
  const Result merged = run("merge " + (d / "s0").string() + " " + (d / "s1").string() + " --out " +
                            (d / "merged").string() + " --db " + db);
  ASSERT_EQ(merged.code, 0) << merged.err;
  EXPECT_EQ(merged.out, (d / "merged" / "index.html").string() + "\n");
  EXPECT_NE(slurp(d / "merged" / "index.html").find("class=\"aoeval-viewer\""), std::string::npos);
}

}  // namespace
