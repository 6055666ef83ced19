// The parameter declarations and the registry: defaults, ranges, unknown keys, text values.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"

namespace aoeval {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Params, DefaultsFillEveryDeclaredParameter) {
  const EstimatorInfo& e = find_estimator("raytraced");
  const ParamSet p = resolve_params(e.name, e.params, nlohmann::json::object(), "test");
  for (const auto& spec : e.params) EXPECT_EQ(p.json()[spec.name], spec.default_value) << spec.name;
  EXPECT_EQ(p.integer("rays"), 16);
  EXPECT_EQ(p.choice("weighting"), "cosine");
}

TEST(Params, TextValuesAreParsedByType) {
  const EstimatorInfo& e = find_estimator("raytraced");
  const ParamSet p = resolve_params(
      e.name, e.params, parse_set_arguments({"rays=64", "dmax=0.5", "falloff=linear"}), "--set");
  EXPECT_EQ(p.integer("rays"), 64);
  EXPECT_DOUBLE_EQ(p.real("dmax"), 0.5);
  const AoDefinition d = e.definition(p);
  EXPECT_EQ(d.falloff, Falloff::linear);
  EXPECT_DOUBLE_EQ(d.dmax, 0.5);
  // power:K through falloff = power and its exponent falloff_k (CONTRACT §3).
  const AoDefinition cubic = e.definition(
      resolve_params(e.name, e.params,
                     parse_set_arguments({"dmax=0.5", "falloff=power", "falloff_k=3"}), "--set"));
  EXPECT_EQ(cubic.falloff, Falloff::power(3.0));
  EXPECT_EQ(cubic.label(), "cosine/dmax:0.5/power:3");
}

TEST(Params, ErrorsNameTheKeyAndTheAllowedRange) {
  const EstimatorInfo& e = find_estimator("raytraced");
  auto resolve = [&](std::vector<std::string> sets) {
    return error_of([&] { resolve_params(e.name, e.params, parse_set_arguments(sets), "--set"); });
  };
  std::string msg = resolve({"rayz=4"});
  EXPECT_NE(msg.find("unknown parameter 'rayz'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("rays"), std::string::npos) << msg;  // lists the known ones
  msg = resolve({"rays=0"});
  EXPECT_NE(msg.find("rays=0"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[1, 65536]"), std::string::npos) << msg;
  msg = resolve({"rays=2.5"});
  EXPECT_NE(msg.find("integer"), std::string::npos) << msg;
  msg = resolve({"weighting=area"});
  EXPECT_NE(msg.find("cosine, uniform"), std::string::npos) << msg;
  msg = resolve({"dmax=abc"});
  EXPECT_NE(msg.find("number"), std::string::npos) << msg;
  // Each error is the one its input earns, not any error.
  EXPECT_EQ(error_of([] { parse_set_arguments({"rays"}); }),
            "--set: expected KEY=VALUE, got 'rays'");
  EXPECT_EQ(error_of([] {
              parse_set_arguments({"rays=1", "rays=2"});
            }),
            "--set: 'rays' is given twice");
  // A falloff without a range is an invalid definition.
  const ParamSet p =
      resolve_params(e.name, e.params, parse_set_arguments({"falloff=sqrt"}), "--set");
  msg = error_of([&] { e.definition(p); });
  EXPECT_NE(msg.find("--falloff sqrt needs a finite --dmax"), std::string::npos) << msg;
}

TEST(Registry, EveryEstimatorIsWellDeclared) {
  ASSERT_GE(estimator_registry().size(), 2u);
  for (const auto& e : estimator_registry()) {
    EXPECT_FALSE(e.summary.empty()) << e.name;
    EXPECT_FALSE(e.paper.empty()) << e.name;
    EXPECT_TRUE(e.definition && e.create) << e.name;
    for (const auto& p : e.params) {
      EXPECT_FALSE(p.meaning.empty()) << e.name << "." << p.name;
      if (p.type == ParamType::real || p.type == ParamType::integer) {
        EXPECT_LE(p.min, p.default_value.get<double>()) << e.name << "." << p.name;
        EXPECT_GE(p.max, p.default_value.get<double>()) << e.name << "." << p.name;
      }
    }
    const ParamSet defaults = resolve_params(e.name, e.params, nlohmann::json::object(), "test");
    EXPECT_NO_THROW(e.definition(defaults)) << e.name;
  }
  const std::string unknown = error_of([] { find_estimator("nope"); });
  EXPECT_NE(unknown.find("unknown estimator 'nope'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("constant, raytraced"), std::string::npos) << unknown;  // lists them
}

// Commands and runners keep references and pointers into the registry (SweepPoint::estimator)
// while --plugins folders are still being added: adding plug-ins must not move an entry.
TEST(Registry, EntriesStayWhereTheyAreWhenPlugInsAreAdded) {
  const EstimatorInfo* constant = &find_estimator("constant");
  const EstimatorInfo* first = &estimator_registry().front();
  const size_t before = estimator_registry().size();
  const std::filesystem::path root = testutil::test_temp_dir("registry_stable");
  for (int i = 0; i < 40; ++i) {  // enough to make a vector reallocate several times
    const std::filesystem::path folder = root / ("copy-" + std::to_string(i));
    std::filesystem::create_directories(folder);
    std::ofstream(folder / "estimator.json") << nlohmann::json{
        {"name", "stable-copy-" + std::to_string(i)},
        {"summary", "a copy"},
        {"paper", "none"},
        {"kind", "process"},
        {"command", {"/bin/true"}},
        {"params", nlohmann::json::array()},
        {"definition", {{"weighting", "cosine"}, {"dmax", nullptr}, {"falloff", "none"}}},
        {"outputs", {"AO"}}}.dump();
    add_plugin_dir(folder.string());
  }
  ASSERT_EQ(estimator_registry().size(), before + 40);
  EXPECT_EQ(&find_estimator("constant"), constant);
  EXPECT_EQ(&estimator_registry().front(), first);
  EXPECT_EQ(constant->name, "constant");
}

TEST(Params, FormattingIsShortAndStable) {
  EXPECT_EQ(format_param_value(0.2), "0.2");
  EXPECT_EQ(format_param_value(8), "8");
  EXPECT_EQ(format_param_value(true), "true");
  EXPECT_EQ(format_param_value("cosine"), "cosine");
}

// A built-in's code version is computed at build time from its folder (code_versions.h): every
// built-in has one, and estimators of one folder share it.
TEST(Registry, EveryBuiltInHasACodeVersion) {
  std::string hbao, hbao_cpu;
  for (const EstimatorInfo& e : estimator_registry()) {
    if (e.kind != "built-in") continue;
    EXPECT_EQ(estimator_code_version(e).rfind("built-in:", 0), 0u)
        << e.name << ": " << estimator_code_version(e);
    EXPECT_EQ(estimator_code_version(e).size(), 9u + 12u)
        << e.name << ": " << estimator_code_version(e);
    if (e.name == "hbao-split") hbao = estimator_code_version(e);
    if (e.name == "hbao-split-cpu") hbao_cpu = estimator_code_version(e);
  }
  EXPECT_EQ(hbao, hbao_cpu);
  EXPECT_NE(estimator_code_version(find_estimator("gtao")),
            estimator_code_version(find_estimator("rtao")));
}

}  // namespace
}  // namespace aoeval
