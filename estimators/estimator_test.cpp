// The parameter declarations and the registry: defaults, ranges, unknown keys, text values.
#include <gtest/gtest.h>

#include "base/errors.h"
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
  EXPECT_FALSE(error_of([] { parse_set_arguments({"rays"}); }).empty());
  EXPECT_FALSE(error_of([] { parse_set_arguments({"rays=1", "rays=2"}); }).empty());
  // A falloff without a range is an invalid definition.
  const ParamSet p =
      resolve_params(e.name, e.params, parse_set_arguments({"falloff=sqrt"}), "--set");
  EXPECT_THROW(e.definition(p), InputError);
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
  EXPECT_THROW(find_estimator("nope"), InputError);
}

TEST(Params, FormattingIsShortAndStable) {
  EXPECT_EQ(format_param_value(0.2), "0.2");
  EXPECT_EQ(format_param_value(8), "8");
  EXPECT_EQ(format_param_value(true), "true");
  EXPECT_EQ(format_param_value("cosine"), "cosine");
}

}  // namespace
}  // namespace aoeval
