// `tune_compare`: the optimisers of tune_search.h side by side on closed-form problems shaped like
// AO tuning, so the default is picked with numbers (README "Tuning"). Not a test: it prints a
// table. Each problem's optimum under its budget is found by enumerating the integer lattice (the
// real coordinate's optimum is known in closed form); the table gives, per algorithm and evaluation
// count, the mean relative gap of the best point found to that optimum and the share of problems
// solved within 2 %.
//
//   hbao-like:  e = a/Nd + b/Ns + c log10(R/R0)^2 + d/(1+Nn),  t = t0 + k Nd Ns (1 + Nn/2)
//   rays-like:  e = s/sqrt(rays) x (sampler factor), t = t0 + k rays (sampler cost)
#include <cmath>
#include <cstdio>
#include <random>

#include "harness/tune/tune_search.h"

namespace aoeval {
namespace {

struct Problem {
  nlohmann::json doc;
  std::function<Outcome(const nlohmann::json&)> f;
  double optimum = 0.0;
};

std::vector<Problem> problems() {
  std::vector<Problem> out;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 12; ++i) {
    const double a = 0.02 + 0.08 * u(rng), b = 0.02 + 0.08 * u(rng), c = 0.05 + 0.2 * u(rng),
                 d = 0.01 + 0.04 * u(rng), r0 = 0.1 + 0.6 * u(rng), k = 0.02 + 0.05 * u(rng);
    const double budget = 3.0 + 20.0 * u(rng);
    Problem p;
    p.doc = {{"estimator", "hbao-split-cpu"},
             {"params", {{"R", {0.05, 1.0}}, {"Nd", {2, 24}}, {"Ns", {2, 32}}, {"Nn", {0, 3}}}},
             {"budget_ms", budget}};
    p.f = [=](const nlohmann::json& o) {
      const double nd = o["Nd"].get<double>(), ns = o["Ns"].get<double>(),
                   nn = o["Nn"].get<double>();
      const double l = std::log10(o["R"].get<double>() / r0);
      Outcome o2;
      o2.objective = a / nd + b / ns + c * l * l + d / (1.0 + nn);
      o2.time_ms = 0.5 + k * nd * ns * (1.0 + nn / 2.0);
      o2.feasible = o2.time_ms <= budget;
      return o2;
    };
    p.optimum = 1e9;
    for (int nd = 2; nd <= 24; ++nd)
      for (int ns = 2; ns <= 32; ++ns)
        for (int nn = 0; nn <= 3; ++nn)
          if (0.5 + k * nd * ns * (1.0 + nn / 2.0) <= budget)
            p.optimum = std::min(p.optimum, a / nd + b / ns + d / (1.0 + nn));
    out.push_back(p);
  }
  for (int i = 0; i < 6; ++i) {
    const double s = 0.2 + 0.2 * u(rng), k = 0.01 + 0.05 * u(rng), budget = 2.0 + 30.0 * u(rng);
    Problem p;
    p.doc = {{"estimator", "raytraced"},
             {"params", {{"rays", {1, 4096}}, {"sampler", "all"}}},
             {"budget_ms", budget}};
    const double factor[3] = {1.0, 0.7, 0.5}, cost[3] = {1.0, 1.1, 1.3};
    auto index = [](const std::string& name) {
      return name == "random" ? 0 : name == "stratified" ? 1 : 2;
    };
    p.f = [=](const nlohmann::json& o) {
      const int j = index(o["sampler"]);
      const double rays = o["rays"].get<double>();
      Outcome o2;
      o2.objective = s / std::sqrt(rays) * factor[j];
      o2.time_ms = 0.3 + k * rays * cost[j];
      o2.feasible = o2.time_ms <= budget;
      return o2;
    };
    p.optimum = 1e9;
    for (int j = 0; j < 3; ++j)
      for (int rays = 1; rays <= 4096; ++rays)
        if (0.3 + k * rays * cost[j] <= budget)
          p.optimum = std::min(p.optimum, s / std::sqrt(rays) * factor[j]);
    out.push_back(p);
  }
  return out;
}

}  // namespace
}  // namespace aoeval

int main() {
  using namespace aoeval;
  const auto list = problems();
  std::printf("%-16s %5s %12s %12s %10s %12s %12s %10s\n", "algorithm", "evals", "hbao gap",
              "hbao <=2%", "hbao inf", "rays gap", "rays <=2%", "rays inf");
  for (const std::string& algorithm : tune_algorithms()) {
    for (const int evaluations : {30, 60}) {
      double gap[2] = {0, 0};
      int within[2] = {0, 0}, none[2] = {0, 0}, count[2] = {0, 0};
      for (const auto& p : list) {
        const nlohmann::json doc = {{"name", "c"}, {"scenes", {"bunny"}}, {"tune", p.doc}};
        const TuneSpec spec = parse_tune_spec(doc, "compare");
        SearchSettings s;
        s.algorithm = algorithm;
        s.evaluations = evaluations;
        s.budget_ms = spec.budget_ms;
        const SearchResult r = search(make_tune_space(spec), s, p.f);
        const int kind = p.doc["estimator"] == "raytraced";
        ++count[kind];
        if (r.best < 0) {
          ++none[kind];
          gap[kind] += 1.0;
          continue;
        }
        const double g = r.trials[static_cast<size_t>(r.best)].outcome.objective / p.optimum - 1.0;
        gap[kind] += g;
        within[kind] += g <= 0.02;
      }
      std::printf("%-16s %5d %11.2f%% %6d of %2d %10d %11.2f%% %6d of %2d %10d\n",
                  algorithm.c_str(), evaluations, 100 * gap[0] / count[0], within[0], count[0],
                  none[0], 100 * gap[1] / count[1], within[1], count[1], none[1]);
    }
  }
  return 0;
}
