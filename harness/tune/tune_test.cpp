// The tuner's pieces without running an estimator: the spec's validation (every bad input names
// its field), the search space's rounding, the budget's judgement and the search itself on
// closed-form problems whose optimum is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "base/errors.h"
#include "harness/tune/tune_budget.h"
#include "harness/tune/tune_search.h"
#include "harness/tune/tune_spec.h"

namespace aoeval {
namespace {

nlohmann::json hbao_spec(nlohmann::json tune) {
  return {{"name", "t"}, {"scenes", {"bunny"}}, {"res", {32, 24}}, {"tune", std::move(tune)}};
}

nlohmann::json hbao_tune() {
  return {{"estimator", "hbao-split-cpu"},
          {"params", {{"R", {0.05, 1.0}}, {"Nd", {2, 24}}, {"Ns", {2, 32}}}},
          {"fixed", {{"Nn", 1}}},
          {"objective", "rmse_excess"},
          {"budget_ms", 40},
          {"evaluations", 60}};
}

std::string error_of(const nlohmann::json& doc) {
  try {
    parse_tune_spec(doc, "spec.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TuneSpec, ReadsTheContractExampleInDeclarationOrderWithTheDeclaredScales) {
  nlohmann::json t = hbao_tune();
  t["params"] = {{"Ns", {2, 32}}, {"R", {0.05, 1.0}}, {"Nd", {2, 24}}};  // JSON order differs
  const TuneSpec s = parse_tune_spec(hbao_spec(t), "spec.json");
  ASSERT_EQ(s.params.size(), 3u);
  EXPECT_EQ(s.params[0].spec->name, "R");
  EXPECT_TRUE(s.params[0].log_scale);  // R is declared log-scale
  EXPECT_EQ(s.params[1].spec->name, "Nd");
  EXPECT_FALSE(s.params[1].log_scale);
  EXPECT_EQ(s.objective, "rmse_excess");
  EXPECT_FALSE(s.maximise);
  EXPECT_EQ(s.budget_ms, 40.0);
  EXPECT_EQ(s.evaluations, 60);
  EXPECT_EQ(s.sweep.runs.at(0).fixed, nlohmann::json({{"Nn", 1}}));
}

TEST(TuneSpec, BadInputNamesTheField) {
  auto with = [](const std::string& key, nlohmann::json value) {
    nlohmann::json t = hbao_tune();
    t[key] = std::move(value);
    return error_of(hbao_spec(t));
  };
  auto param = [](const std::string& key, nlohmann::json value) {
    nlohmann::json t = hbao_tune();
    t["params"][key] = std::move(value);
    return error_of(hbao_spec(t));
  };
  std::string e = param("Rx", {0.1, 0.2});
  EXPECT_NE(e.find("tune.params.Rx"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown parameter of hbao-split-cpu"), std::string::npos) << e;
  e = param("Nd", {2, 100});
  EXPECT_NE(e.find("tune.params.Nd"), std::string::npos) << e;
  EXPECT_NE(e.find("outside the declared range [1, 64]"), std::string::npos) << e;
  e = param("R", {0.0, 1.0});
  EXPECT_NE(e.find("outside the declared range"), std::string::npos) << e;
  e = param("Nd", {2.5, 8});
  EXPECT_NE(e.find("integer bounds"), std::string::npos) << e;
  e = param("Nd", {8, 8});
  EXPECT_NE(e.find("lo < hi"), std::string::npos) << e;
  e = param("Nn", {0, 2});
  EXPECT_NE(e.find("both params and fixed"), std::string::npos) << e;
  e = param("seed", {1, 5});
  EXPECT_NE(e.find("tune.params.seed"), std::string::npos) << e;
  e = param("blur", {"yes"});
  EXPECT_NE(e.find("tune.params.blur"), std::string::npos) << e;
  e = with("objective", "rmse_exces");
  EXPECT_NE(e.find("tune.objective"), std::string::npos) << e;
  EXPECT_NE(e.find("not a metric key"), std::string::npos) << e;
  e = with("objective", "pixels");
  EXPECT_NE(e.find("not an error measure"), std::string::npos) << e;
  e = with("budget", 40);
  EXPECT_NE(e.find("tune.budget"), std::string::npos) << e;
  e = with("budget_ms", -1);
  EXPECT_NE(e.find("tune.budget_ms"), std::string::npos) << e;
  e = with("fixed", {{"Nn", 99}});
  EXPECT_NE(e.find("Nn"), std::string::npos) << e;
  e = with("estimator", "hbao-nope");
  EXPECT_NE(e.find("tune.estimator"), std::string::npos) << e;
  e = with("optimiser", {{"algorithm", "newton"}});
  EXPECT_NE(e.find("tune.optimiser.algorithm"), std::string::npos) << e;
  nlohmann::json doc = hbao_spec(hbao_tune());
  doc["runs"] = nlohmann::json::array();
  EXPECT_NE(error_of(doc).find("runs"), std::string::npos);
  doc = hbao_spec(hbao_tune());
  doc["scens"] = {"bunny"};
  EXPECT_NE(error_of(doc).find("scens"), std::string::npos);
  // A sequence score on a still view (bunny's first, or "all": still views only) has no value.
  for (const nlohmann::json& views : {nlohmann::json(), nlohmann::json("all")}) {
    doc = hbao_spec(hbao_tune());
    doc["tune"]["objective"] = "steady_rmse_excess";
    if (!views.is_null()) doc["views"] = views;
    e = error_of(doc);
    EXPECT_NE(e.find("tune.objective: 'steady_rmse_excess' is a sequence score"), std::string::npos)
        << e;
  }
  e = with("objective", "seq_frames");
  EXPECT_NE(e.find("not an error measure"), std::string::npos) << e;
}

// The sequence scores (CONTRACT §10) on a sequence view (bunny's orbit), the others on the first.
TEST(TuneSpec, TakesEveryObjectiveKeyAndItsTrueTwin) {
  const std::vector<std::string> sequence_keys = tune_sequence_objective_keys();
  EXPECT_EQ(sequence_keys,
            std::vector<std::string>({"seq_rmse_excess", "steady_rmse_excess", "temporal_rmse",
                                      "temporal_rmse_excess", "converge_frames", "settle_frames",
                                      "disocclusion_rmse_excess", "lag_rmse_excess"}));
  for (const auto& key : tune_objective_keys()) {
    const bool sequence =
        std::find(sequence_keys.begin(), sequence_keys.end(), key) != sequence_keys.end();
    for (const std::string prefix : {"", "true_"}) {
      nlohmann::json t = hbao_tune();
      t["objective"] = prefix + key;
      nlohmann::json doc = hbao_spec(t);
      if (sequence) doc["views"] = {"orbit"};
      EXPECT_EQ(error_of(doc), "") << prefix + key;
      if (sequence) {
        EXPECT_TRUE(parse_tune_spec(doc, "s").sequence_objective) << key;
      }
    }
  }
  nlohmann::json t = hbao_tune();
  t["objective"] = "ssim";
  EXPECT_TRUE(parse_tune_spec(hbao_spec(t), "s").maximise);
}

// A sum of keys is one objective (the anti-lag tunes' lag + steady): its terms in order, each a key
// a single objective could be; a term that grows with quality, a repeated term or an unknown one
// exits 2 naming tune.objective.
TEST(TuneSpec, TakesASumOfErrorKeys) {
  nlohmann::json t = hbao_tune();
  t["objective"] = "lag_rmse_excess+true_steady_rmse_excess";
  nlohmann::json doc = hbao_spec(t);
  doc["views"] = {"orbit"};
  const TuneSpec s = parse_tune_spec(doc, "s");
  EXPECT_EQ(s.objective_terms,
            std::vector<std::string>({"lag_rmse_excess", "true_steady_rmse_excess"}));
  EXPECT_TRUE(s.sequence_objective);
  EXPECT_FALSE(s.maximise);
  EXPECT_EQ(parse_tune_spec(hbao_spec(hbao_tune()), "s").objective_terms,
            std::vector<std::string>({"rmse_excess"}));
  for (const std::string bad : {"rmse_excess+ssim", "rmse_excess+rmse_excess", "rmse_excess+",
                                "rmse_excess+pixels", "rmse_excess+lag"}) {
    t["objective"] = bad;
    doc["tune"] = t;
    const std::string e = error_of(doc);
    EXPECT_NE(e.find("tune.objective"), std::string::npos) << bad << ": " << e;
  }
  t["objective"] = "rmse_excess+lag_rmse_excess";  // a sequence term needs sequence views
  EXPECT_NE(error_of(hbao_spec(t)).find("is a sequence score"), std::string::npos);
}

// u = 0 and u = 1 give the range's ends; each integer owns an equal share of u; reals keep 3
// significant digits; choices and booleans enumerate in mixed radix, the last fastest.
TEST(TuneSpace, RoundsIntegersFairlyAndRealsTo3DigitsAndEnumeratesChoices) {
  nlohmann::json t = hbao_tune();
  t["estimator"] = "raytraced";
  t["params"] = {{"rays", {1, 64}}, {"dmax", {0.1, 2.0}}, {"sampler", "all"}};
  t["fixed"] = nlohmann::json::object();
  const TuneSpec s = parse_tune_spec(hbao_spec(t), "s");
  const TuneSpace space = make_tune_space(s);
  ASSERT_EQ(space.numeric.size(), 2u);
  ASSERT_EQ(space.combinations(), 3u);
  EXPECT_EQ(space.decode(0, {0.0, 0.0})["rays"], 1);
  EXPECT_EQ(space.decode(0, {1.0, 1.0})["rays"], 64);
  EXPECT_EQ(space.decode(0, {0.0, 0.0})["dmax"], 0.1);
  EXPECT_EQ(space.decode(0, {0.0, 1.0})["dmax"], 2.0);
  EXPECT_EQ(space.decode(0, {0.0, 0.5})["dmax"], 1.05);  // linear (dmax is not log-scale)
  EXPECT_EQ(space.decode(0, {0.0, 0.123456})["dmax"], 0.335);
  EXPECT_EQ(space.decode(2, {0.0, 0.0})["sampler"], "sobol");
  // rays is log-scale: u spans [0.5, 64.5] geometrically, so each integer's share of u is
  // log((k + 0.5) / (k - 0.5)) / log(129): 1 owns log 3 / log 129 = 0.226.
  std::map<int64_t, int> counts;
  for (int i = 0; i < 10000; ++i) counts[space.decode(0, {(i + 0.5) / 10000.0, 0.0})["rays"]]++;
  EXPECT_EQ(counts.size(), 64u);
  EXPECT_NEAR(counts[1] / 10000.0, std::log(3.0) / std::log(129.0), 1e-3);
  EXPECT_NEAR(counts[64] / 10000.0, std::log(64.5 / 63.5) / std::log(129.0), 1e-3);
  EXPECT_NEAR(space.encode(0, 8.0), std::log(8.0 / 0.5) / std::log(129.0), 1e-12);
}

TEST(TuneBudget, JudgesBySpreadAndPooledMedian) {
  // Two views; means: min 9.5, median 10, max 10.5.
  const std::vector<std::vector<double>> s = {{9, 10, 11}, {10, 10, 10}};
  EXPECT_EQ(judge_time(s, 10.5, false).verdict, TimeVerdict::feasible);
  EXPECT_EQ(judge_time(s, 10.4, false).verdict, TimeVerdict::borderline);
  EXPECT_EQ(judge_time(s, 9.5, false).verdict, TimeVerdict::borderline);
  EXPECT_EQ(judge_time(s, 9.49, false).verdict, TimeVerdict::infeasible);
  EXPECT_EQ(judge_time(s, 10.0, true).verdict, TimeVerdict::feasible);
  EXPECT_EQ(judge_time(s, 9.99, true).verdict, TimeVerdict::infeasible);
  EXPECT_EQ(judge_time(s, 0.0, false).verdict, TimeVerdict::feasible);  // no budget
  const TimeJudgement j = judge_time(s, 10.0, false);
  EXPECT_DOUBLE_EQ(j.mean_median, 10.0);
  EXPECT_DOUBLE_EQ(j.mean_min, 9.5);
  EXPECT_DOUBLE_EQ(j.mean_max, 10.5);
  EXPECT_DOUBLE_EQ(median_of({4, 1, 3, 2}), 2.5);
}

// A closed-form problem shaped like AO tuning: error falls with the sample count n and has an
// interior optimum in a log-scale radius x; time grows with n; a choice doubles the cost and
// lowers the error. Under a budget of 20 the optimum is n = 19, mode b, x = 0.5 (error
// 0.02 + 0.4 / 19). Every algorithm must find a feasible point; the default must find the optimum.
TEST(TuneSearch, FindsTheClosedFormOptimumUnderTheBudget) {
  nlohmann::json t = {
      {"estimator", "raytraced"},
      {"params", {{"rays", {1, 64}}, {"dmax", {0.01, 10.0}}, {"sampler", {"random", "sobol"}}}},
      {"budget_ms", 20},
      {"evaluations", 60}};
  const TuneSpec spec = parse_tune_spec(hbao_spec(t), "s");
  const TuneSpace space = make_tune_space(spec);
  for (const std::string algorithm :
       {"direct-l+sbplx", "direct-l", "sbplx", "bobyqa", "cobyla", "isres"}) {
    SearchSettings settings;
    settings.algorithm = algorithm;
    settings.evaluations = 60;
    settings.budget_ms = 20;
    int calls = 0;
    std::set<std::string> seen;
    const SearchResult r = search(space, settings, [&](const nlohmann::json& o) {
      ++calls;
      EXPECT_TRUE(seen.insert(o.dump()).second) << "evaluated twice: " << o.dump();
      const int64_t n = o["rays"];
      const bool b = o["sampler"] == "sobol";
      const double l = std::log10(o["dmax"].get<double>() / 0.5);
      Outcome out;
      out.objective = 0.02 + 0.1 * l * l + 0.4 / static_cast<double>(n) + (b ? 0.0 : 0.05);
      out.time_ms = 0.5 + static_cast<double>(n) * (b ? 1.0 : 0.5);
      out.feasible = out.time_ms <= 20.0;
      return out;
    });
    EXPECT_LE(calls, 60) << algorithm;
    EXPECT_EQ(static_cast<int>(r.trials.size()), calls);
    ASSERT_GE(r.best, 0) << algorithm;
    const Trial& best = r.trials[static_cast<size_t>(r.best)];
    EXPECT_TRUE(best.outcome.feasible);
    if (algorithm == "direct-l+sbplx") {
      EXPECT_EQ(best.overrides["rays"], 19) << best.overrides.dump();
      EXPECT_EQ(best.overrides["sampler"], "sobol");
      EXPECT_NEAR(best.outcome.objective, 0.02 + 0.4 / 19.0, 1e-3) << best.overrides.dump();
    }
  }
}

}  // namespace
}  // namespace aoeval
