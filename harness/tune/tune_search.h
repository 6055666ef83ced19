// The search behind `aoeval tune`: a maintained optimiser (NLopt, Debian's libnlopt-cxx-dev) over
// the numeric parameters, an outer loop over the combinations of choices and booleans, and a cache
// keyed by the rounded point, so a point the optimiser proposes twice is evaluated once.
//
// The space. Each numeric parameter is one coordinate u in [0, 1]: linear, or logarithmic where the
// declaration says so (R, rays: equal steps in u are equal ratios). Integers are rounded, with
// each integer owning an equal share of u (u spans [lo - 1/2, hi + 1/2] before rounding, so the
// end values are not half as likely). Reals are rounded to 3 significant digits: closer points are
// the same evaluation (AO does not resolve them, and for estimators whose definition follows a
// parameter, e.g. dmax = R, each distinct value costs a reference).
//
// The budget is a constraint, not a trade: the optimiser minimises
//     objective                          where the point is feasible,
//     kInfeasible * (1 + time / budget)  where it is not (or where its rows were skipped),
// so every feasible point ranks below every infeasible one whatever the objective's scale, and an
// infeasible point ranks worse the further it is over the budget (the way back). cobyla and
// isres receive the budget as NLopt's inequality constraint time / budget - 1 <= 0 instead.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "harness/tune/tune_spec.h"

namespace aoeval {

inline constexpr double kInfeasible = 1e3;

struct TuneSpace {
  std::vector<const TuneParam*> numeric;      // one coordinate each
  std::vector<const TuneParam*> categorical;  // choices and booleans: the outer loop
  nlohmann::json fixed = nlohmann::json::object();
  size_t combinations() const;  // product of the categorical value counts (1 when none)
  // The overrides (fixed + every searched parameter) of combination `c` at u (rounded as above).
  nlohmann::json decode(size_t c, const std::vector<double>& u) const;
  // u of a value of numeric parameter k (clamped into [0, 1]): where a search starts.
  double encode(size_t k, double value) const;
};
TuneSpace make_tune_space(const TuneSpec& spec);

// What one evaluated point gave: its objective (already oriented: lower is better), its time
// (mean over views of the median) and whether it meets the budget (tune_budget.h).
struct Outcome {
  bool ok =
      true;  // false: a row was skipped (the estimator's backend is missing, a plug-in failed)
  double objective = 0.0;
  double time_ms = 0.0;
  bool feasible = true;
};

struct Trial {
  nlohmann::json overrides;
  Outcome outcome;
  size_t combination = 0;
};

struct SearchSettings {
  std::string algorithm = kDefaultTuneAlgorithm;
  int evaluations = kDefaultTuneEvaluations;  // distinct points
  uint64_t seed = kDefaultTuneSeed;
  double budget_ms = 0.0;  // 0: no budget (every ok point is feasible)
};

struct SearchResult {
  std::vector<Trial> trials;  // distinct points in the order first evaluated
  int best = -1;              // index into trials of the best feasible point, -1 when none
  int calls = 0;              // objective calls the optimiser made (cache hits included)
  bool stopped = false;       // the evaluate callback asked to stop (SIGINT)
  nlohmann::json settings;    // the optimiser and its settings, for tune.json
};

// Thrown by an evaluate callback to end the search between two points (SIGINT): search() returns
// what it has with stopped = true.
struct SearchStopped {};

using EvaluateFn = std::function<Outcome(const nlohmann::json& overrides)>;
// Deterministic: the same space, settings and outcomes give the same sequence of points, which is
// what lets a re-run replay an interrupted tune from its stored rows.
SearchResult search(const TuneSpace& space, const SearchSettings& settings,
                    const EvaluateFn& evaluate);

// The value the optimiser minimises for an outcome (see above).
double barrier_value(const Outcome& o, double budget_ms);

}  // namespace aoeval
