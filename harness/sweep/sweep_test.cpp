// Sweep specifications: expansion counts, ranges, shards, validation messages.
#include <gtest/gtest.h>

#include <set>

#include "base/errors.h"
#include "harness/evaluation/evaluation.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {
namespace {

nlohmann::json spec_with(nlohmann::json runs) {
  return {{"name", "t"}, {"scenes", {"cornell-box", "bunny"}}, {"res", {32, 24}}, {"runs", runs}};
}

TEST(Sweep, GridIsACartesianProductOverScenes) {
  const SweepSpec s = parse_sweep_spec(
      spec_with({{{"estimator", "raytraced"},
                  {"grid", {{"rays", {1, 4, 16}}, {"sampler", {"random", "sobol"}}}},
                  {"fixed", {{"weighting", "cosine"}}}},
                 {{"estimator", "constant"}}}),
      "spec.json");
  const auto points = expand_sweep(s);
  EXPECT_EQ(points.size(), (3u * 2u + 1u) * 2u);
  std::set<std::string> names;
  for (const auto& p : points) names.insert(p.name);
  EXPECT_EQ(names.size(), points.size());
  EXPECT_TRUE(
      names.count("raytraced/rays:16/weighting:cosine/sampler:sobol/scene:bunny/view:main/32x24"))
      << *names.begin();
  EXPECT_TRUE(names.count("constant/scene:cornell-box/view:main/32x24"));
}

TEST(Sweep, AllViewsMultiplies) {
  nlohmann::json j = spec_with({{{"estimator", "constant"}}});
  j["views"] = "all";
  EXPECT_EQ(expand_sweep(parse_sweep_spec(j, "spec.json")).size(), 4u);  // 2 scenes x 2 views
  j["views"] = {"main"};
  EXPECT_EQ(expand_sweep(parse_sweep_spec(j, "spec.json")).size(), 2u);
}

// "scene/view" names that scene's view alone, so one sweep or tune can hold the sequences of
// several scenes (rolling-ball/roll and dragon/walk); a plain name still applies to every scene.
TEST(Sweep, AQualifiedViewBelongsToItsSceneAlone) {
  nlohmann::json j = spec_with({{{"estimator", "constant"}}});
  j["views"] = {"bunny/orbit", "cornell-box/corner", "main"};
  std::set<std::string> got;
  for (const auto& p : expand_sweep(parse_sweep_spec(j, "spec.json")))
    got.insert(p.scene + "/" + p.view);
  EXPECT_EQ(got, (std::set<std::string>{"bunny/orbit", "bunny/main", "cornell-box/corner",
                                        "cornell-box/main"}));
  j["views"] = {"bunny/orbit"};  // cornell-box is left with no view: an error, not a silent gap
  try {
    expand_sweep(parse_sweep_spec(j, "spec.json"));
    ADD_FAILURE() << "a scene with no view expanded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none applies to scene cornell-box"), std::string::npos)
        << e.what();
  }
  j["views"] = {"dragon/walk"};  // not one of the spec's scenes: a view name, which bunny lacks
  EXPECT_THROW(expand_sweep(parse_sweep_spec(j, "spec.json")), InputError);
}

TEST(Sweep, RangesLinearLogAndIntegerDedup) {
  const ParamSpec real = real_param({.name = "R",
                                     .def = 0.5,
                                     .min = 0.0,
                                     .max = 10.0,
                                     .spacing = Spacing::linear,
                                     .unit = "",
                                     .meaning = "r"});
  auto v = expand_grid_values(real, {{"range", {0.0, 1.0, 5}}}, "f.json", "w");
  ASSERT_EQ(v.size(), 5u);
  EXPECT_DOUBLE_EQ(v[2].get<double>(), 0.5);
  v = expand_grid_values(real, {{"range", {0.1, 10.0, 3}}, {"scale", "log"}}, "f.json", "w");
  ASSERT_EQ(v.size(), 3u);
  EXPECT_NEAR(v[1].get<double>(), 1.0, 1e-12);
  const ParamSpec integer = int_param({.name = "N",
                                       .def = 4,
                                       .min = 1,
                                       .max = 100,
                                       .spacing = Spacing::log,
                                       .unit = "",
                                       .meaning = "n"});
  v = expand_grid_values(integer, {{"range", {1, 4, 10}}, {"scale", "lin"}}, "f.json", "w");
  EXPECT_EQ(v.size(), 4u);  // 1, 1.33, 1.67, 2, ... rounded and deduplicated
  EXPECT_THROW(
      expand_grid_values(real, {{"range", {0.0, 1.0, 5}}, {"scale", "log"}}, "f.json", "w"),
      InputError);
  EXPECT_THROW(expand_grid_values(real, {{"range", {0.0, 1.0}}}, "f.json", "w"), InputError);
  EXPECT_THROW(expand_grid_values(real, {{"rnage", {0.0, 1.0, 2}}}, "f.json", "w"), InputError);
}

// A range without "scale" follows the parameter's declared spacing: geometric for a log_scale
// parameter (1, 10, 100, 1000), arithmetic otherwise (1, 334, 667, 1000).
TEST(Sweep, RangeWithoutScaleFollowsTheDeclaredScale) {
  const ParamSpec logp = int_param({.name = "rays",
                                    .def = 16,
                                    .min = 1,
                                    .max = 65536,
                                    .spacing = Spacing::log,
                                    .unit = "rays",
                                    .meaning = "n"});
  auto v = expand_grid_values(logp, {{"range", {1, 1000, 4}}}, "f.json", "w");
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[1].get<int64_t>(), 10);
  EXPECT_EQ(v[2].get<int64_t>(), 100);
  const ParamSpec linp = int_param({.name = "rays",
                                    .def = 16,
                                    .min = 1,
                                    .max = 65536,
                                    .spacing = Spacing::linear,
                                    .unit = "rays",
                                    .meaning = "n"});
  v = expand_grid_values(linp, {{"range", {1, 1000, 4}}}, "f.json", "w");
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[1].get<int64_t>(), 334);
  EXPECT_EQ(v[2].get<int64_t>(), 667);
}

TEST(Sweep, ShardsPartitionThePoints) {
  const auto points = expand_sweep(parse_sweep_spec(
      spec_with({{{"estimator", "raytraced"}, {"grid", {{"rays", {1, 2, 3, 4, 5}}}}}}),
      "spec.json"));
  for (int n : {1, 2, 3, 7}) {
    std::multiset<std::string> all;
    for (int i = 0; i < n; ++i)
      for (const auto& p : select_shard(points, i, n)) all.insert(p.name);
    ASSERT_EQ(all.size(), points.size()) << n;
    for (const auto& p : points) EXPECT_EQ(all.count(p.name), 1u) << n;
  }
  EXPECT_EQ(parse_shard("1/4"), std::make_pair(1, 4));
  for (const char* bad : {"4/4", "1", "a/b", "-1/2", "1/0"})
    EXPECT_THROW(parse_shard(bad), InputError) << bad;
}

std::string error_of(const nlohmann::json& j) {
  try {
    parse_sweep_spec(j, "spec.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Sweep, ValidationNamesTheFieldAndTheKey) {
  std::string msg = error_of(spec_with({{{"estimator", "raytraced"}, {"grid", {{"rayz", {1}}}}}}));
  EXPECT_NE(msg.find("unknown parameter 'rayz'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("spec.json"), std::string::npos) << msg;
  msg = error_of(spec_with({{{"estimator", "raytraced"}, {"grid", {{"rays", {0}}}}}}));
  EXPECT_NE(msg.find("rays=0"), std::string::npos) << msg;
  msg = error_of(spec_with({{{"estimator", "hbao-nope"}}}));
  EXPECT_NE(msg.find("runs[0].estimator"), std::string::npos) << msg;
  msg = error_of(spec_with(
      {{{"estimator", "raytraced"}, {"grid", {{"rays", {1}}}}, {"fixed", {{"rays", 2}}}}}));
  EXPECT_NE(msg.find("both"), std::string::npos) << msg;
  nlohmann::json j = spec_with({{{"estimator", "constant"}}});
  j["timming"] = {{"warmup", 1}};
  msg = error_of(j);
  EXPECT_NE(msg.find("timming"), std::string::npos) << msg;
  j = spec_with({{{"estimator", "constant"}}});
  j["scenes"] = {"no-such-scene"};
  EXPECT_FALSE(error_of(j).empty());
}

// An estimator whose backend is missing (EstimatorUnavailable from prepare) gives a "skipped" row
// with its reason and no metrics, instead of ending the sweep.
TEST(Evaluation, UnavailableBackendGivesASkippedRow) {
  struct Unavailable : Estimator {
    void prepare(const EstimateContext&) override {
      throw EstimatorUnavailable("no Vulkan device (test: no driver)");
    }
    EstimateResult run(const EstimateContext&) override { return {}; }
  };
  EstimatorInfo info;
  info.name = "unavailable";
  info.backend = Backend::vulkan;
  info.definition = [](const ParamSet&) { return AoDefinition{}; };
  info.create = [](const ParamSet&) { return std::make_unique<Unavailable>(); };
  EvaluationSession session(ReferenceSpec{}, TimingSpec{}, false);
  EvaluationRequest req;
  req.estimator = &info;
  req.scene = "cornell-box";
  req.width = 16;
  req.height = 12;
  const ResultRow row = session.evaluate(req);
  EXPECT_EQ(row.status, "skipped: no Vulkan device (test: no driver)");
  EXPECT_TRUE(row.metrics.empty());
  EXPECT_TRUE(row.true_metrics.empty());
  EXPECT_EQ(row.repetitions, 0);
  EXPECT_EQ(row.backend, "vulkan");
  EXPECT_TRUE(session.last_estimate().empty());
}

}  // namespace
}  // namespace aoeval
