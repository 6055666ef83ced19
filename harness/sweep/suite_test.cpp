// Suites: the shipped files parse, points are deduplicated and featured as harness/suite.h says,
// and --set ESTIMATOR:KEY=VALUE replaces grid and fixed values or names what is wrong.
#include "harness/sweep/suite.h"

#include <gtest/gtest.h>

#include "base/errors.h"

namespace aoeval {
namespace {

nlohmann::json spec(const std::string& name, nlohmann::json runs) {
  return {{"name", name},
          {"scenes", {"cornell-box"}},
          {"res", {16, 16}},
          {"reference", {{"spp", 4}}},
          {"runs", std::move(runs)}};
}

std::vector<std::string> names(const std::vector<SuitePoint>& points) {
  std::vector<std::string> n;
  for (const auto& p : points) n.push_back(p.point.name + (p.featured ? " *" : ""));
  return n;
}

TEST(Suite, ShippedSuitesParse) {
  const auto shipped = shipped_suites();
  for (const char* name : {"quick", "default", "paper", "levels"}) {
    EXPECT_NE(std::find(shipped.begin(), shipped.end(), name), shipped.end()) << name;
    const Suite s = load_suite(name);
    EXPECT_EQ(s.name, name);
    EXPECT_FALSE(expand_suite(s).empty()) << name;
  }
}

TEST(Suite, UnknownSuiteNamesTheShippedOnes) {
  try {
    load_suite("nosuch");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nosuch"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("quick"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_suite("/nonexistent/suite.json"), InputError);
}

TEST(Suite, TheDefaultPointIsFeaturedAndAGridCopyOfItRunsOnce) {
  // rays=16 is raytraced's default: the grid's rays:16 point computes what the gridless run does.
  const nlohmann::json doc = nlohmann::json::array(
      {spec("a", {{{"estimator", "raytraced"}},
                  {{"estimator", "raytraced"}, {"grid", {{"rays", {4, 16}}}}}})});
  const auto points = expand_suite(parse_suite(doc, "s.json", "s"));
  EXPECT_EQ(names(points),
            (std::vector<std::string>{"raytraced/scene:cornell-box/view:main/16x16 *",
                                      "raytraced/rays:4/scene:cornell-box/view:main/16x16"}));
}

TEST(Suite, ASweepWithoutADefaultPointFeaturesItsFirstPoint) {
  const nlohmann::json doc =
      spec("a", {{{"estimator", "raytraced"}, {"grid", {{"rays", {2, 8}}}}}});
  const auto points = expand_suite(parse_suite(doc, "s.json", "s"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_TRUE(points[0].featured);
  EXPECT_FALSE(points[1].featured);
}

TEST(Suite, PointsOfTwoSpecsDifferingInTheirReferenceBothRun) {
  nlohmann::json second = spec("b", {{{"estimator", "constant"}}});
  second["reference"]["spp"] = 8;
  const nlohmann::json doc =
      nlohmann::json::array({spec("a", {{{"estimator", "constant"}}}), second});
  const auto points = expand_suite(parse_suite(doc, "s.json", "s"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].spec, 0u);
  EXPECT_EQ(points[1].spec, 1u);
}

TEST(Suite, BadSuiteDocumentsNameTheFileAndSpec) {
  EXPECT_THROW(parse_suite(nlohmann::json::array(), "s.json", "s"), InputError);
  EXPECT_THROW(parse_suite(42, "s.json", "s"), InputError);
  try {
    parse_suite(nlohmann::json::array({spec("a", {{{"estimator", "nope"}}})}), "s.json", "s");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.json[0]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
  }
}

TEST(Suite, SetReplacesGridAndFixedValuesOfThatEstimatorOnly) {
  const nlohmann::json doc =
      spec("a", {{{"estimator", "raytraced"}},
                 {{"estimator", "raytraced"}, {"grid", {{"rays", {4, 16}}}}},
                 {{"estimator", "obscurances"}, {"grid", {{"rays", {4, 16}}}}}});
  Suite s = parse_suite(doc, "s.json", "s");
  apply_suite_overrides(s, {parse_suite_override("raytraced:rays=2")});
  EXPECT_EQ(names(expand_suite(s)),
            (std::vector<std::string>{"raytraced/rays:2/scene:cornell-box/view:main/16x16 *",
                                      "obscurances/rays:4/scene:cornell-box/view:main/16x16 *",
                                      "obscurances/rays:16/scene:cornell-box/view:main/16x16"}));
}

TEST(Suite, BadSetsNameWhatIsWrong) {
  Suite s = parse_suite(spec("a", {{{"estimator", "raytraced"}}}), "s.json", "s");
  auto message = [&](const std::string& text) -> std::string {
    try {
      apply_suite_overrides(s, {parse_suite_override(text)});
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message("nope:rays=2").find("nope"), std::string::npos);
  EXPECT_NE(message("raytraced:rayz=2").find("rayz"), std::string::npos);
  EXPECT_NE(message("raytraced:rays=0").find("[1, 65536]"), std::string::npos);
  EXPECT_NE(message("tree-sphere:alpha_scale=2").find("does not run"), std::string::npos);
  for (const char* bad : {"raytraced", "raytraced=4", ":rays=4", "raytraced:=4"})
    EXPECT_THROW(parse_suite_override(bad), InputError) << bad;
}

}  // namespace
}  // namespace aoeval
