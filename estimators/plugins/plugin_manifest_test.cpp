// estimator.json validation: every rule a built-in's table follows, each error naming the file and
// the field; the shipped examples pass; a name clash with a built-in is an error.
#include "estimators/plugins/plugin_manifest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "estimators/plugins/plugin_test_util.h"
#include "estimators/registry.h"

namespace aoeval {
namespace {

using plugin_test::make_plugin;
using testutil::test_temp_dir;
namespace fs = std::filesystem;

const char* kValid = R"({
  "name": "my-ssao", "summary": "one line", "paper": "someone, 2024",
  "kind": "process", "command": ["/bin/sh", "run.sh"],
  // comments are allowed
  "params": [
    {"name": "radius", "type": "real", "default": 0.5, "min": 0.01, "max": 5, "scale": "log",
     "unit": "scene units", "meaning": "world-space radius"},
    {"name": "taps", "type": "integer", "default": 8, "min": 1, "max": 64, "meaning": "taps"},
    {"name": "blur", "type": "boolean", "default": true, "meaning": "blur"},
    {"name": "mode", "type": "choice", "choices": ["a", "b"], "default": "b", "meaning": "mode"}
  ],
  "definition": {"weighting": "uniform", "dmax": "radius", "falloff": "linear"},
  "outputs": ["AO", "bent"], "timeout_s": 3, "frames": 4
})";

// The manifest of kValid with one edit: `from` replaced by `to`.
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kValid;
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

std::string error_of(const std::string& manifest) {
  const std::string dir = make_plugin(test_temp_dir("manifest") / "p", manifest);
  try {
    read_plugin_manifest(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PluginManifest, ReadsEveryField) {
  const PluginManifest m =
      read_plugin_manifest(make_plugin(test_temp_dir("manifest") / "p", kValid));
  EXPECT_EQ(m.name, "my-ssao");
  EXPECT_EQ(m.kind, PluginKind::process);
  ASSERT_EQ(m.params.size(), 4u);
  EXPECT_EQ(m.params[0].name, "radius");
  EXPECT_TRUE(m.params[0].log_scale);
  EXPECT_EQ(m.params[1].default_value, 8);
  EXPECT_EQ(m.params[2].type, ParamType::boolean);
  EXPECT_EQ(m.params[3].choices, (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(m.bent);
  EXPECT_EQ(m.timeout_s, 3.0);
  EXPECT_EQ(m.frames, 4);
  // dmax follows the parameter it names.
  const ParamSet p = resolve_params(m.name, m.params, {{"radius", 0.25}}, "test");
  const AoDefinition d = plugin_definition(m, p);
  EXPECT_EQ(d.weighting, Weighting::uniform);
  EXPECT_EQ(d.dmax, 0.25);
  EXPECT_EQ(d.falloff, Falloff::linear);
}

// CONTRACT §3 power:K in a manifest: what a volumetric-obscurance plug-in declares.
TEST(PluginManifest, DeclaresAPowerFalloff) {
  const PluginManifest m = read_plugin_manifest(
      make_plugin(test_temp_dir("manifest") / "p",
                  edited("\"falloff\": \"linear\"", "\"falloff\": \"power:3\"")));
  const AoDefinition d = plugin_definition(m, resolve_params(m.name, m.params, {}, "test"));
  EXPECT_EQ(d.falloff, Falloff::power(3.0));
  EXPECT_EQ(d.to_json()["falloff"], "power:3");
  EXPECT_NE(plugin_definition_doc(m).find("falloff power:3"), std::string::npos);
  for (const char* bad : {"power:0", "power:-1", "power:nan", "power:x"}) {
    const std::string e =
        error_of(edited("\"falloff\": \"linear\"", std::string("\"falloff\": \"") + bad + "\""));
    EXPECT_NE(e.find(std::string("definition.falloff: \"") + bad + "\""), std::string::npos) << e;
  }
}

TEST(PluginManifest, EachErrorNamesTheFileAndTheField) {
  const std::string file = (test_temp_dir("manifest") / "p" / "estimator.json").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {edited("\"default\": 0.5", "\"default\": 7"), "params[0].default: 7 is outside [0.01, 5]"},
      {edited("\"min\": 0.01", "\"min\": 0"), "params[0].scale: log scale needs a positive range"},
      {edited("\"name\": \"taps\"", "\"name\": \"radius\""), "params[1].name: duplicate name"},
      {edited("\"meaning\": \"blur\"", "\"meaning\": \"\""),
       "params[2].meaning: must not be empty"},
      {edited("\"default\": \"b\"", "\"default\": \"c\""),
       "params[3].default: \"c\" is not one of"},
      {edited("\"type\": \"boolean\"", "\"type\": \"flag\""),
       "params[2].type: \"flag\" is not one"},
      {edited("\"default\": 8", "\"default\": 8.5"), "params[1].default: expected an integer"},
      {edited("\"unit\": \"scene units\"", "\"units\": \"m\""), "params[0].units: unknown field"},
      {edited("\"dmax\": \"radius\"", "\"dmax\": \"taps2\""),
       "definition.dmax: \"taps2\" names no"},
      {edited("\"dmax\": \"radius\"", "\"dmax\": null"),
       "definition.falloff: falloff linear needs"},
      {edited("\"weighting\": \"uniform\"", "\"weighting\": \"flat\""), "definition.weighting"},
      {edited("\"outputs\": [\"AO\", \"bent\"]", "\"outputs\": [\"bent\"]"), "outputs: must hold"},
      {edited("\"timeout_s\": 3", "\"timeout_s\": 0"), "timeout_s: must be in (0, 86400]"},
      {edited("\"kind\": \"process\"", "\"kind\": \"dll\""),
       "kind: \"dll\" is not process or glsl"},
      {edited("\"command\": [\"/bin/sh\", \"run.sh\"]", "\"command\": []"), "command: expected a"},
      {edited("\"name\": \"my-ssao\"", "\"name\": \"My SSAO\""), "name: \"My SSAO\" must be"},
      {edited("\"summary\": \"one line\", ", ""), "summary: missing"},
      {edited("\"frames\": 4", "\"colour\": 4"), "colour: unknown field"},
      {"{\"name\": ", "not JSON"},
  };
  for (const auto& [manifest, expected] : cases) {
    const std::string e = error_of(manifest);
    EXPECT_EQ(e.rfind(file + ": ", 0), 0u) << e;
    EXPECT_NE(e.find(expected), std::string::npos) << "expected \"" << expected << "\" in: " << e;
  }
}

TEST(PluginManifest, GlslShadersMustExistAndHaveDistinctPassNames) {
  const std::string glsl = R"({"name": "g", "summary": "s", "kind": "glsl",
      "shaders": ["a.comp", "sub/a.comp"], "definition": {"weighting": "cosine"}})";
  const auto dir = test_temp_dir("manifest") / "g";
  EXPECT_NE(error_of(glsl).find("shaders[0]: "), std::string::npos) << error_of(glsl);
  make_plugin(dir, glsl, {{"a.comp", "x"}, {"sub/a.comp", "x"}});
  try {
    read_plugin_manifest(dir.string());
    ADD_FAILURE() << "two passes named a";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shaders[1]: two shaders named \"a\""), std::string::npos)
        << e.what();
  }
}

TEST(PluginManifest, ShippedExamplesAreValidAndRegistered) {
  std::vector<std::string> names;
  for (const auto& folder : plugin_folders_in(shipped_plugins_dir()))
    names.push_back(read_plugin_manifest(folder).name);
  EXPECT_EQ(names, (std::vector<std::string>{"alchemy", "constant-copy", "crytek-ssao",
                                             "crytek-ssao-frames", "history-ssao", "sao"}));
  EXPECT_EQ(find_estimator("alchemy").kind, "glsl");
  EXPECT_EQ(find_estimator("alchemy").backend, Backend::vulkan);
  EXPECT_EQ(find_estimator("crytek-ssao").kind, "process");
  EXPECT_EQ(find_estimator("crytek-ssao").backend, Backend::process);
  EXPECT_EQ(find_estimator("constant").kind, "built-in");
}

// Issue 32: a shipped example whose folder holds a tune.json ships that tune's best point as its
// defaults (every effective parameter, the held ones included, the seed aside), and says so in
// the meanings ("paper preset" beside each tuned default). constant-copy has no tune (no quality
// knob); crytek-ssao-frames declares crytek-ssao's table (FramesProtocol checks it).
TEST(PluginManifest, ShippedExamplesDefaultToTheirTunesBest) {
  std::vector<std::string> tuned;
  for (const auto& folder : plugin_folders_in(shipped_plugins_dir())) {
    const fs::path tune = fs::path(folder) / "tune.json";
    if (!fs::exists(tune)) continue;
    const PluginManifest m = read_plugin_manifest(folder);
    tuned.push_back(m.name);
    EXPECT_TRUE(fs::exists(fs::path(folder) / "tune-spec.json")) << m.name;
    std::ifstream in(tune);
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j.at("status"), "complete") << m.name;
    ASSERT_TRUE(j.at("feasible").get<bool>()) << m.name;
    EXPECT_EQ(j.at("estimator"), m.name);
    const nlohmann::json& best = j.at("best").at("effective_params");
    for (const ParamSpec& p : m.params) {
      if (p.name == "seed") continue;
      ASSERT_TRUE(best.contains(p.name)) << m.name << "." << p.name;
      if (p.type == ParamType::real) {
        EXPECT_DOUBLE_EQ(p.default_value.get<double>(), best.at(p.name).get<double>())
            << m.name << "." << p.name;
      } else {
        EXPECT_EQ(p.default_value, best.at(p.name)) << m.name << "." << p.name;
      }
      if (j.at("best").at("params").contains(p.name)) {
        EXPECT_NE(p.meaning.find("paper preset"), std::string::npos) << m.name << "." << p.name;
      }
    }
  }
  EXPECT_EQ(tuned, (std::vector<std::string>{"alchemy", "crytek-ssao", "history-ssao", "sao"}));
}

// A clash is a warning when the plug-ins are read and an error for whoever asks for the name
// (tree-volume: a built-in no other test of this binary uses).
TEST(PluginManifest, ANameClashWithABuiltInIsAnErrorWhenUsed) {
  const auto dir = test_temp_dir("manifest") / "clash";
  make_plugin(dir, edited("\"name\": \"my-ssao\"", "\"name\": \"tree-volume\""));
  testing::internal::CaptureStderr();
  add_plugin_dir(dir.string());
  estimator_registry();  // a command that lists estimators: the warnings are said here
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("warning: plug-in \"tree-volume\" (" + dir.string() + ") is skipped"),
            std::string::npos)
      << warning;
  try {
    find_estimator("tree-volume");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("estimator.json: name: \"tree-volume\" is already a built-in"),
        std::string::npos)
        << e.what();
  }
  // The same folder twice is read once; another folder with the same name is skipped.
  const auto a = test_temp_dir("manifest") / "a", b = test_temp_dir("manifest") / "b";
  make_plugin(a, edited("\"name\": \"my-ssao\"", "\"name\": \"twice\""));
  make_plugin(b, edited("\"name\": \"my-ssao\"", "\"name\": \"twice\""));
  add_plugin_dir(a.string());
  add_plugin_dir(a.string());
  EXPECT_EQ(find_estimator("twice").folder, a.string());
  testing::internal::CaptureStderr();
  add_plugin_dir(b.string());
  estimator_registry();
  EXPECT_NE(testing::internal::GetCapturedStderr().find("is already the plug-in of " + a.string()),
            std::string::npos);
}

// Values nested 100,000 deep (a crash before: the error message recursed through them) and a
// number no double holds are one-line InputErrors naming the file (and the key).
TEST(PluginManifest, ADeepValueOrAHugeNumberIsAClearError) {
  const std::string file = (test_temp_dir("manifest") / "p" / "estimator.json").string();
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  for (const std::string where : {"\"frames\": 4", "\"default\": 0.5"}) {
    const std::string e = error_of(edited(where, where.substr(0, where.find(':') + 1) + deep));
    EXPECT_EQ(e, file + ": nested deeper than 64 levels");
  }
  std::string deep_object;
  for (int i = 0; i < 100000; ++i) deep_object += "{\"a\": ";
  deep_object += "0" + std::string(100000, '}');
  EXPECT_EQ(error_of(deep_object), file + ": nested deeper than 64 levels");
  EXPECT_EQ(error_of(edited("\"max\": 5", "\"max\": 1e400")),
            file + ": max: a number too large for a double");
  // Within the limit, a container where a scalar belongs is named by kind, not printed.
  EXPECT_NE(error_of(edited("\"frames\": 4", "\"frames\": [[[[1]]]]"))
                .find("frames: expected a number, got an array"),
            std::string::npos);
}

// One broken plug-in folder does not take the others down: each is a warning naming it (all of
// them, not the first), the good one and the built-ins work, and asking for a broken one is the
// InputError that says why.
TEST(PluginManifest, BrokenPluginsAreWarningsUntilUsed) {
  const auto root = test_temp_dir("manifest") / "mixed";
  std::filesystem::remove_all(root);
  make_plugin(root / "good", edited("\"name\": \"my-ssao\"", "\"name\": \"mixed-good\""));
  make_plugin(root / "not-json", "{\"name\": ");
  make_plugin(root / "deep", "{\"name\": \"mixed-deep\", \"x\": " + std::string(100000, '[') +
                                 std::string(100000, ']') + "}");
  std::string range = edited("\"name\": \"my-ssao\"", "\"name\": \"mixed-range\"");
  range.replace(range.find("\"default\": 0.5"), 14, "\"default\": 7");
  make_plugin(root / "bad-range", range);
  testing::internal::CaptureStderr();
  add_plugin_dir(root.string());
  estimator_registry();
  const std::string err = testing::internal::GetCapturedStderr();
  for (const std::string& named : {"\"not-json\" (" + (root / "not-json").string() + ")",
                                   "\"mixed-deep\" (" + (root / "deep").string() + ")",
                                   "\"mixed-range\" (" + (root / "bad-range").string() + ")"})
    EXPECT_NE(err.find("warning: plug-in " + named + " is skipped: "), std::string::npos)
        << named << " in: " << err;
  EXPECT_EQ(find_estimator("mixed-good").folder, (root / "good").string());
  EXPECT_EQ(find_estimator("constant").kind, "built-in");
  for (const auto& [name, why] : std::vector<std::pair<std::string, std::string>>{
           {"not-json", "not JSON"},
           {"mixed-deep", "nested deeper than 64 levels"},
           {"mixed-range", "params[0].default: 7 is outside"}}) {
    try {
      find_estimator(name);
      ADD_FAILURE() << name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("plug-in \"" + name + "\" cannot be used: "),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

// A command that asks for a broken plug-in says why once, as its error: no warning with the same
// text before it. Other broken plug-ins are still warned about.
TEST(PluginManifest, AskingForABrokenPluginSaysWhyOnce) {
  const auto root = test_temp_dir("manifest") / "asked";
  std::filesystem::remove_all(root);
  std::string range = edited("\"name\": \"my-ssao\"", "\"name\": \"asked-range\"");
  range.replace(range.find("\"default\": 0.5"), 14, "\"default\": 7");
  make_plugin(root / "asked", range);
  make_plugin(root / "other", "{\"name\": ");
  testing::internal::CaptureStderr();
  add_plugin_dir(root.string());
  std::string error;
  try {
    find_estimator("asked-range");
  } catch (const InputError& e) {
    error = e.what();
  }
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(error.find("plug-in \"asked-range\" cannot be used: "), std::string::npos) << error;
  EXPECT_NE(error.find("params[0].default: 7 is outside"), std::string::npos) << error;
  EXPECT_EQ(err.find("asked-range"), std::string::npos) << err;
  EXPECT_NE(err.find("warning: plug-in \"other\""), std::string::npos) << err;
}

TEST(PluginManifest, AFolderOfPluginsOrNoneAtAll) {
  const auto root = test_temp_dir("manifest");
  make_plugin(root / "many" / "x", edited("\"name\": \"my-ssao\"", "\"name\": \"x\""));
  make_plugin(root / "many" / "y", edited("\"name\": \"my-ssao\"", "\"name\": \"y\""));
  EXPECT_EQ(plugin_folders_in((root / "many").string()).size(), 2u);
  // Sub-folders that hold no plug-in (a sweep's output beside them) and loose files are passed
  // over, not a listing error.
  std::filesystem::create_directories(root / "many" / "out" / "runs");
  std::ofstream(root / "many" / "sweep.json") << "{}";
  EXPECT_EQ(
      plugin_folders_in((root / "many").string()),
      (std::vector<std::string>{(root / "many" / "x").string(), (root / "many" / "y").string()}));
  std::filesystem::create_directories(root / "empty");
  EXPECT_THROW(plugin_folders_in((root / "empty").string()), InputError);
  EXPECT_THROW(plugin_folders_in((root / "missing").string()), InputError);
}

// The code version names content: a changed shader or script changes it, a file rewritten with
// the same bytes (a new date) or a file the manifest does not name does not; so does the manifest.
TEST(PluginManifest, CodeVersionFollowsTheContentOfTheFilesItNames) {
  const fs::path dir = test_temp_dir("code_version");
  const std::string glsl =
      make_plugin(dir / "g",
                  R"({"name": "g", "summary": "s", "kind": "glsl", "shaders": ["ao.comp"],
          "definition": {"weighting": "cosine"}})",
                  {{"ao.comp", "void main() {}\n"}, {"notes.txt", "a"}});
  const std::string v1 = plugin_code_version(read_plugin_manifest(glsl));
  EXPECT_EQ(v1.rfind("glsl:", 0), 0u) << v1;
  EXPECT_EQ(v1.size(), 5u + 12u) << v1;
  plugin_test::write_file(fs::path(glsl) / "ao.comp", "void main() {}\n");  // same bytes
  plugin_test::write_file(fs::path(glsl) / "notes.txt", "b");               // not named
  EXPECT_EQ(plugin_code_version(read_plugin_manifest(glsl)), v1);
  plugin_test::write_file(fs::path(glsl) / "ao.comp", "void main() { }\n");
  const std::string v2 = plugin_code_version(read_plugin_manifest(glsl));
  EXPECT_NE(v2, v1);

  const std::string process = make_plugin(dir / "p", kValid, {{"run.sh", "exit 0"}});
  const std::string p1 = plugin_code_version(read_plugin_manifest(process));
  EXPECT_EQ(p1.rfind("process:", 0), 0u) << p1;
  plugin_test::write_file(fs::path(process) / "run.sh", "exit 1");
  const std::string p2 = plugin_code_version(read_plugin_manifest(process));
  EXPECT_NE(p2, p1);
  plugin_test::write_file(fs::path(process) / "estimator.json", edited("\"taps\"", "\"tap\""));
  EXPECT_NE(plugin_code_version(read_plugin_manifest(process)), p2);
}

}  // namespace
}  // namespace aoeval
