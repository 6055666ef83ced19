// Plug-ins on the command line (CONTRACT §2, §7): listed with their kind, --set checked like a
// built-in's, --plugins and $AOEVAL_PLUGINS read, a name clash and a compile error exit 2 naming
// the file, a failing plug-in gives a "skipped: <reason>" row and the sweep goes on (and resumes).
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "base/testing/cli_test_util.h"
#include "base/testing/test_temp_dir.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;
using cli_test::Result;
using cli_test::slurp;

fs::path temp_dir() {
  return testutil::test_temp_dir("plugins_cli");
}

Result run(const std::string& args, const std::string& env = "") {
  const fs::path d = temp_dir();
  return cli_test::run_aoeval("AOEVAL_CACHE=" + (d / "cache").string() + " " + env, args, d);
}

size_t lines(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A shell-script process plug-in named `name` in `dir`.
void shell_plugin(const fs::path& dir, const std::string& name, const std::string& script) {
  write(dir / "estimator.json", R"({"name": ")" + name + R"(", "summary": "test plug-in",
      "kind": "process", "command": ["/bin/sh", "run.sh"], "timeout_s": 20,
      "params": [{"name": "level", "type": "real", "default": 0.5, "min": 0, "max": 1,
                  "meaning": "the AO it writes"}],
      "definition": {"weighting": "cosine"}})");
  write(dir / "run.sh", script);
}

TEST(PluginsCli, ListShowsTheShippedExamplesWithTheirKind) {
  const Result r = run("estimators list");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* line : {"alchemy          glsl     vulkan", "sao              glsl     vulkan",
                           "crytek-ssao      process  process", "constant-copy    process  process",
                           "constant         built-in cpu"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  const Result show = run("estimators show sao --json");
  ASSERT_EQ(show.code, 0) << show.err;
  const auto j = nlohmann::json::parse(show.out);
  EXPECT_EQ(j["kind"], "glsl");
  EXPECT_EQ(j["params"][0]["name"], "radius");
  // dmax is the parameter radius, at its declared (tuned, issue 32) default
  EXPECT_EQ(j["definition_at_defaults"]["dmax"], j["params"][0]["default"]);
  EXPECT_EQ(j["definition_at_defaults"]["dmax"], 1.51);
}

TEST(PluginsCli, SetOnAPluginChecksKeysAndRanges) {
  const fs::path out = temp_dir() / "e.exr";
  Result r = run("estimate --estimator alchemy --scene cornell-box --res 16x16 --set radiuz=1 -o " +
                 out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("radiuz"), std::string::npos) << r.err;
  r = run("estimate --estimator alchemy --scene cornell-box --res 16x16 --set samples=0 -o " +
          out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("samples=0"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(PluginsCli, PluginsOptionAndEnvironmentAndNameClash) {
  const fs::path d = temp_dir();
  shell_plugin(d / "mine" / "mine", "mine", "exit 0\n");
  shell_plugin(d / "env" / "from-env", "from-env", "exit 0\n");
  Result r = run("estimators list --plugins " + (d / "mine").string(),
                 "AOEVAL_PLUGINS=/nonexistent-but-skipped-no:" + (d / "env").string() + " ");
  // A missing folder in AOEVAL_PLUGINS is a warning: the other plug-ins and built-ins still work.
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: $AOEVAL_PLUGINS: plug-in folder /nonexistent-but-skipped-no"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("from-env "), std::string::npos) << r.out;
  r = run("estimators list --plugins " + (d / "mine").string(),
          "AOEVAL_PLUGINS=" + (d / "env").string() + " ");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mine "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("from-env "), std::string::npos) << r.out;

  // A clash with a built-in: a warning for a command that does not use the name, exit 2 for one
  // that does.
  shell_plugin(d / "clash", "raytraced", "exit 0\n");
  r = run("estimators list --plugins " + (d / "clash").string());
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find((d / "clash" / "estimator.json").string() + ": name: \"raytraced\""),
            std::string::npos)
      << r.err;
  r = run("estimators show raytraced --plugins " + (d / "clash").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: --estimator: plug-in \"raytraced\" cannot be used: " +
                       (d / "clash" / "estimator.json").string() + ": name: \"raytraced\""),
            std::string::npos)
      << r.err;
  write(d / "badparam" / "estimator.json", R"({"name": "bad", "summary": "s", "kind": "process",
      "command": ["x"], "definition": {"weighting": "cosine"},
      "params": [{"name": "r", "type": "real", "default": 2, "min": 0, "max": 1, "meaning": "m"}]})");
  r = run("estimators show bad --plugins " + (d / "badparam").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("estimator.json: params[0].default: 2 is outside [0, 1]"), std::string::npos)
      << r.err;
}

TEST(PluginsCli, AGlslCompileErrorExitsTwoNamingFileAndLine) {
  const fs::path d = temp_dir() / "glsl-broken";
  write(d / "estimator.json", R"({"name": "glsl-broken", "summary": "s", "kind": "glsl",
      "shaders": ["ao.comp"], "definition": {"weighting": "cosine"}})");
  write(d / "ao.comp", "#version 450\nlayout(local_size_x = 8) in;\nvoid main() {\n  nope();\n}\n");
  const fs::path out = temp_dir() / "g.exr";
  const Result r =
      run("estimate --plugins " + d.string() +
          " --estimator glsl-broken --scene cornell-box --res 16x16 -o " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find((d / "ao.comp").string() + ":4:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// Must-show 2 of issue 28: one good and three broken plug-ins in one folder. `estimators list`
// lists the good one and warns about each broken one by name; a sweep of built-ins runs; a sweep
// that uses a broken one exits 2 before writing anything.
TEST(PluginsCli, OneGoodAndThreeBrokenPlugins) {
  const fs::path d = temp_dir() / "mixed";
  fs::remove_all(d);
  shell_plugin(d / "plugs" / "fine", "fine", "exit 0\n");
  write(d / "plugs" / "not-json" / "estimator.json", "{\"name\": ");
  write(d / "plugs" / "deep" / "estimator.json",
        "{\"name\": \"deep\", \"x\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
  write(d / "plugs" / "no-program" / "estimator.json",
        R"({"name": "no-program", "summary": "s", "kind": "process", "command": ["prog.sh"],
            "definition": {"weighting": "cosine"}})");
  const std::string plugs = " --plugins " + (d / "plugs").string();
  Result r = run("estimators list" + plugs);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("fine "), std::string::npos) << r.out;
  EXPECT_EQ(lines(r.err), 3u) << r.err;
  for (const char* name : {"\"not-json\"", "\"deep\"", "\"no-program\""})
    EXPECT_NE(r.err.find(std::string("warning: plug-in ") + name), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nested deeper than 64 levels"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\"prog.sh\" is neither a file in the plug-in folder nor a program on PATH"),
            std::string::npos)
      << r.err;

  auto spec = [&](const std::string& estimator) {
    write(d / (estimator + ".json"), R"({"name": "mixed", "scenes": ["cornell-box"], "res": [8, 6],
      "reference": {"spp": 1, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
      "runs": [{"estimator": "constant"}, {"estimator": ")" +
                                         estimator + R"("}]})");
    return "sweep " + (d / (estimator + ".json")).string() + " --out " +
           (d / ("out-" + estimator)).string() + " --db " + (d / (estimator + ".sqlite")).string() +
           plugs;
  };
  r = run(spec("raytraced"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "out-raytraced" / "results.json"));
  for (const char* broken : {"deep", "no-program", "not-json"}) {
    r = run(spec(broken));
    EXPECT_EQ(r.code, 2) << broken << ": " << r.err;
    EXPECT_NE(r.err.find(std::string("plug-in \"") + broken + "\" cannot be used"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / (std::string("out-") + broken))) << broken;
    EXPECT_FALSE(fs::exists(d / (std::string(broken) + ".sqlite"))) << broken;
  }
}

// A GLSL plug-in that does not compile stops a sweep before its first point: exit 2 naming the
// shader's file and line, no output folder, no database (issue 28: it used to abort halfway).
TEST(PluginsCli, AGlslCompileErrorStopsASweepBeforeAnything) {
  const fs::path d = temp_dir() / "sweep-compile";
  fs::remove_all(d);
  write(d / "plug" / "estimator.json", R"({"name": "late-error", "summary": "s", "kind": "glsl",
      "shaders": ["ao.comp"], "definition": {"weighting": "cosine"},
      "params": [{"name": "r", "type": "real", "default": 0.5, "min": 0, "max": 1, "meaning": "m"}]})");
  write(d / "plug" / "ao.comp",
        "#version 450\nlayout(local_size_x = 8) in;\nvoid main() {\n  nope();\n}\n");
  write(d / "spec.json", R"({"name": "late", "scenes": ["cornell-box"], "res": [8, 6],
      "reference": {"spp": 1, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
      "runs": [{"estimator": "constant"}, {"estimator": "late-error"}]})");
  const Result r =
      run("sweep " + (d / "spec.json").string() + " --out " + (d / "out").string() + " --db " +
          (d / "r.sqlite").string() + " --plugins " + (d / "plug").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find((d / "plug" / "ao.comp").string() + ":4:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out"));
  EXPECT_FALSE(fs::exists(d / "r.sqlite"));
  // tune reads its estimator the same way.
  write(d / "tune.json", R"({"name": "late-tune", "scenes": ["cornell-box"], "res": [8, 6],
      "reference": {"spp": 1}, "timing": {"warmup": 0, "repetitions": 1},
      "tune": {"estimator": "late-error", "params": {"r": [0.1, 0.9]}, "objective": "rmse_excess",
               "budget_ms": 1000, "evaluations": 2}})");
  const Result t =
      run("tune " + (d / "tune.json").string() + " --out " + (d / "out").string() + " --db " +
          (d / "r.sqlite").string() + " --plugins " + (d / "plug").string());
  EXPECT_EQ(t.code, 2);
  EXPECT_EQ(lines(t.err), 1u) << t.err;
  EXPECT_NE(t.err.find((d / "plug" / "ao.comp").string() + ":4:"), std::string::npos) << t.err;
  EXPECT_FALSE(fs::exists(d / "out"));
  EXPECT_FALSE(fs::exists(d / "r.sqlite"));
}

TEST(PluginsCli, AbiPrintsTheBindingsAndAPluginsPreamble) {
  Result r = run("estimators abi");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("binding = 7) uniform AoevalFrame"), std::string::npos) << r.out;
  r = run("estimators abi alchemy");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("  float radius;"), std::string::npos) << r.out;
  EXPECT_EQ(run("estimators abi crytek-ssao").code, 2);
}

// A failing plug-in is a skipped row quoting its stderr; the good plug-in and the built-in in the
// same sweep are scored; --resume keeps the rows; estimate exits 1 with the same reason.
TEST(PluginsCli, AFailingPluginIsASkippedRowAndTheSweepGoesOn) {
  const fs::path d = temp_dir();
  fs::remove_all(d / "plugs");
  shell_plugin(d / "plugs" / "broken", "broken", "echo 'segment 3: out of memory' >&2\nexit 4\n");
  shell_plugin(
      d / "plugs" / "good", "good",
      "exec /usr/bin/python3 -c \"import OpenImageIO as o, numpy as np, json, sys; "
      "g = o.ImageInput.open(sys.argv[2]); s = g.spec(); "
      "v = json.load(open(sys.argv[4]))['level']; "
      "out = o.ImageOutput.create(sys.argv[6]); spec = o.ImageSpec(s.width, s.height, 1, 'float'); "
      "spec.channelnames = ('AO',); out.open(sys.argv[6], spec); "
      "out.write_image(np.full((s.height, s.width, 1), v, dtype=np.float32)); out.close()\" "
      "\"$@\"\n");
  write(d / "spec.json", R"({"name": "plugins", "scenes": ["cornell-box"], "res": [24, 18],
    "reference": {"spp": 4, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 2},
    "runs": [{"estimator": "broken"}, {"estimator": "good", "grid": {"level": [0.25, 0.75]}},
             {"estimator": "constant"}]})");
  fs::remove_all(d / "sweep");
  fs::remove_all(d / "tmp");
  fs::create_directories(d / "tmp");
  const std::string args = "sweep " + (d / "spec.json").string() + " --out " +
                           (d / "sweep").string() + " --db " + (d / "r.sqlite").string() +
                           " --plugins " + (d / "plugs").string();
  const std::string env = "TMPDIR=" + (d / "tmp").string() + " ";
  Result r = run(args, env);
  ASSERT_EQ(r.code, 0) << r.err;
  auto rows = nlohmann::json::parse(slurp(d / "sweep" / "results.json"))["rows"];
  ASSERT_EQ(rows.size(), 4u);
  int good = 0;
  std::map<double, double> bias_of_level;
  for (const auto& row : rows) {
    if (row["estimator"] == "broken") {
      EXPECT_EQ(row["status"],
                "skipped: plug-in broken exited with status 4: segment 3: out of memory");
      EXPECT_EQ(row["backend"], "process");
    } else if (row["estimator"] == "good") {
      ++good;
      EXPECT_EQ(row["status"], "ok");
      EXPECT_EQ(row["backend"], "process");
      EXPECT_EQ(row["timing_source"], "process-wall");
      // AO = level everywhere: the bias against the reference follows the level.
      EXPECT_TRUE(row["rmse"].is_number());
      EXPECT_TRUE(row["process_ms"].is_number());
      bias_of_level[row["level"].get<double>()] = row["bias"].get<double>();
    } else {
      EXPECT_EQ(row["status"], "ok");
      EXPECT_EQ(row["timing_source"], "wall");
    }
  }
  EXPECT_EQ(good, 2);
  // AO = level on every pixel, against the same reference: the biases differ by the levels' 0.5.
  ASSERT_EQ(bias_of_level.size(), 2u);
  EXPECT_NEAR(bias_of_level[0.75] - bias_of_level[0.25], 0.5, 1e-6);
  EXPECT_TRUE(fs::is_empty(d / "tmp")) << "the plug-ins' private folders are removed";
  r = run(args + " --resume", env);
  ASSERT_EQ(r.code, 0) << r.err;
  rows = nlohmann::json::parse(slurp(d / "sweep" / "results.json"))["rows"];
  EXPECT_EQ(rows.size(), 4u);

  const fs::path out = d / "b.exr";
  r = run("estimate --plugins " + (d / "plugs").string() +
          " --estimator broken --scene cornell-box --res 16x16 -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("skipped: plug-in broken exited with status 4: segment 3: out of memory"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace aoeval
