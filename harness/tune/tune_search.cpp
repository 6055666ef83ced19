#include "harness/tune/tune_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <map>
#include <nlopt.hpp>

namespace aoeval {

namespace {

// 3 significant digits (see tune_search.h).
double round_significant(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return std::strtod(text, nullptr);
}

// The radical inverse of i in base b: the Halton sequence, where restarts begin (deterministic,
// spread over the box).
double halton(uint64_t i, uint64_t base) {
  double f = 1.0, r = 0.0;
  for (; i > 0; i /= base) {
    f /= static_cast<double>(base);
    r += f * static_cast<double>(i % base);
  }
  return r;
}

constexpr uint64_t kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};

// One search over the numeric coordinates of one combination, sharing the cache and the trial list.
class CombinationSearch {
 public:
  CombinationSearch(const TuneSpace& space, const SearchSettings& s, const EvaluateFn& evaluate,
                    SearchResult& result, std::map<std::string, size_t>& cache, size_t combination)
      : space_(space),
        s_(s),
        evaluate_(evaluate),
        result_(result),
        cache_(cache),
        c_(combination),
        d_(space.numeric.size()) {}

  // Runs `algorithm` from u0 until it has evaluated `budget` new points, converged, or made
  // max_calls calls. Returns the number of new points.
  int run(nlopt::algorithm algorithm, std::vector<double> u0, int budget, double step,
          bool constrained) {
    budget_ = budget;
    new_points_ = 0;
    if (budget <= 0) return 0;
    nlopt::opt opt(algorithm, static_cast<unsigned>(d_));
    opt.set_lower_bounds(std::vector<double>(d_, 0.0));
    opt.set_upper_bounds(std::vector<double>(d_, 1.0));
    opt.set_min_objective(&CombinationSearch::objective, this);
    if (constrained && s_.budget_ms > 0.0)
      opt.add_inequality_constraint(&CombinationSearch::constraint, this, 1e-3);
    // Cache hits are free, but a search circling on a lattice of integers must still end.
    opt.set_maxeval(50 * budget + 20);
    std::vector<double> xtol(d_), steps(d_);
    for (size_t k = 0; k < d_; ++k) {
      const TuneParam& p = *space_.numeric[k];
      const double cells = p.spec->type == ParamType::integer ? p.hi - p.lo + 1.0 : 1000.0;
      xtol[k] = 0.5 / cells;                   // below one integer (or 1/1000 of a real's span)
      steps[k] = std::max(step, 1.0 / cells);  // a first step moves at least one integer
    }
    opt.set_xtol_abs(xtol);
    if (algorithm == nlopt::LN_SBPLX || algorithm == nlopt::LN_BOBYQA ||
        algorithm == nlopt::LN_COBYLA)
      opt.set_initial_step(steps);
    if (algorithm == nlopt::LN_BOBYQA && d_ < 2) return 0;  // BOBYQA needs two coordinates
    for (auto& u : u0) u = std::clamp(u, 0.0, 1.0);
    double value = 0.0;
    try {
      opt.optimize(u0, value);
    } catch (const std::exception&) {
      // forced_stop (the budget, or the callback's own exception) and NLopt's roundoff or
      // failure results all end this run; the points evaluated are kept.
    }
    if (error_) std::rethrow_exception(error_);
    return new_points_;
  }

 private:
  static double objective(const std::vector<double>& u, std::vector<double>&, void* self) {
    auto* me = static_cast<CombinationSearch*>(self);
    return me->value_of(*me->point(u));
  }
  static double constraint(const std::vector<double>& u, std::vector<double>&, void* self) {
    auto* me = static_cast<CombinationSearch*>(self);
    const Outcome* o = me->point(u);
    if (!o->ok) return 1.0;
    return o->time_ms / me->s_.budget_ms - 1.0;
  }

  double value_of(const Outcome& o) const {
    if (!o.ok) return kInfeasible * 4.0;
    return barrier_value(o, s_.budget_ms);
  }

  // The outcome at u: from the cache, or evaluated (throwing forced_stop when this run's budget
  // of new points is spent, or when the callback failed).
  const Outcome* point(const std::vector<double>& u) {
    ++result_.calls;
    nlohmann::json overrides = space_.decode(c_, u);
    const std::string key = overrides.dump();
    if (const auto it = cache_.find(key); it != cache_.end())
      return &result_.trials[it->second].outcome;
    if (new_points_ >= budget_ || error_) throw nlopt::forced_stop();
    Trial t;
    t.overrides = std::move(overrides);
    t.combination = c_;
    try {
      t.outcome = evaluate_(t.overrides);
    } catch (const SearchStopped&) {
      result_.stopped = true;
      error_ = std::current_exception();
      throw nlopt::forced_stop();
    } catch (...) {
      error_ = std::current_exception();
      throw nlopt::forced_stop();
    }
    ++new_points_;
    cache_[key] = result_.trials.size();
    result_.trials.push_back(std::move(t));
    return &result_.trials.back().outcome;
  }

  const TuneSpace& space_;
  const SearchSettings& s_;
  const EvaluateFn& evaluate_;
  SearchResult& result_;
  std::map<std::string, size_t>& cache_;
  size_t c_, d_;
  int budget_ = 0, new_points_ = 0;
  std::exception_ptr error_;
};

}  // namespace

size_t TuneSpace::combinations() const {
  size_t n = 1;
  for (const auto* p : categorical) n *= p->values.size();
  return n;
}

nlohmann::json TuneSpace::decode(size_t c, const std::vector<double>& u) const {
  nlohmann::json out = fixed;
  for (size_t k = categorical.size(); k-- > 0;) {  // mixed radix, the last parameter fastest
    const auto& values = categorical[k]->values;
    out[categorical[k]->spec->name] = values[c % values.size()];
    c /= values.size();
  }
  for (size_t k = 0; k < numeric.size(); ++k) {
    const TuneParam& p = *numeric[k];
    const double t = std::clamp(u[k], 0.0, 1.0);
    if (p.spec->type == ParamType::integer) {
      const double lo = p.lo - 0.5, hi = p.hi + 0.5;
      const double v = p.log_scale ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
      out[p.spec->name] = static_cast<int64_t>(std::clamp(std::round(v), p.lo, p.hi));
    } else {
      const double v = p.log_scale ? p.lo * std::pow(p.hi / p.lo, t) : p.lo + (p.hi - p.lo) * t;
      const double r = round_significant(v);
      out[p.spec->name] = r < p.lo ? p.lo : r > p.hi ? p.hi : r;
    }
  }
  return out;
}

double TuneSpace::encode(size_t k, double value) const {
  const TuneParam& p = *numeric[k];
  double lo = p.lo, hi = p.hi;
  if (p.spec->type == ParamType::integer) {
    lo -= 0.5;
    hi += 0.5;
  }
  const double t =
      p.log_scale ? std::log(value / lo) / std::log(hi / lo) : (value - lo) / (hi - lo);
  return std::clamp(t, 0.0, 1.0);
}

TuneSpace make_tune_space(const TuneSpec& spec) {
  TuneSpace space;
  space.fixed = spec.fixed;
  for (const auto& p : spec.params) (p.numeric() ? space.numeric : space.categorical).push_back(&p);
  return space;
}

double barrier_value(const Outcome& o, double budget_ms) {
  if (!o.ok) return kInfeasible * 4.0;
  if (o.feasible) return o.objective;
  return kInfeasible * (1.0 + o.time_ms / std::max(budget_ms, 1e-12));
}

SearchResult search(const TuneSpace& space, const SearchSettings& s, const EvaluateFn& evaluate) {
  SearchResult result;
  std::map<std::string, size_t> cache;
  const size_t K = space.combinations(), d = space.numeric.size();
  result.settings = {{"library", "NLopt " + std::to_string(nlopt::version_major()) + "." +
                                     std::to_string(nlopt::version_minor()) + "." +
                                     std::to_string(nlopt::version_bugfix())},
                     {"algorithm", s.algorithm},
                     {"evaluations", s.evaluations},
                     {"combinations", K},
                     {"numeric_coordinates", d}};
  if (s.algorithm == "isres") result.settings["seed"] = s.seed;

  auto finish = [&] {
    for (size_t i = 0; i < result.trials.size(); ++i) {
      const Outcome& o = result.trials[i].outcome;
      if (!o.ok || !o.feasible) continue;
      if (result.best < 0) {
        result.best = static_cast<int>(i);
        continue;
      }
      const Outcome& b = result.trials[static_cast<size_t>(result.best)].outcome;
      if (o.objective < b.objective || (o.objective == b.objective && o.time_ms < b.time_ms))
        result.best = static_cast<int>(i);
    }
    return result;
  };

  // Shares of the evaluations: equal per combination, the remainder to the first ones.
  std::vector<int> share(K, 0);
  for (size_t c = 0; c < K; ++c)
    share[c] = s.evaluations / static_cast<int>(K) +
               (static_cast<int>(c) < s.evaluations % static_cast<int>(K) ? 1 : 0);
  result.settings["per_combination"] = share;

  if (d == 0) {  // choices and booleans only: every combination once, in order
    for (size_t c = 0; c < K && static_cast<int>(c) < s.evaluations; ++c) {
      Trial t;
      t.overrides = space.decode(c, {});
      t.combination = c;
      try {
        t.outcome = evaluate(t.overrides);
      } catch (const SearchStopped&) {
        result.stopped = true;
        break;
      }
      result.trials.push_back(std::move(t));
      ++result.calls;
    }
    return finish();
  }

  // Where each search starts: the declared default where it lies in the range, else the middle.
  std::vector<double> start(d, 0.5);
  for (size_t k = 0; k < d; ++k) {
    const TuneParam& p = *space.numeric[k];
    if (p.spec->default_value.is_number()) {
      const double v = p.spec->default_value.get<double>();
      if (v >= p.lo && v <= p.hi) start[k] = space.encode(k, v);
    }
  }
  if (s.algorithm == "isres") nlopt::srand(s.seed);
  const std::map<std::string, nlopt::algorithm> single = {{"direct-l", nlopt::GN_DIRECT_L},
                                                          {"sbplx", nlopt::LN_SBPLX},
                                                          {"bobyqa", nlopt::LN_BOBYQA},
                                                          {"cobyla", nlopt::LN_COBYLA},
                                                          {"isres", nlopt::GN_ISRES}};
  const bool constrained = s.algorithm == "cobyla" || s.algorithm == "isres";
  const bool hybrid = s.algorithm.rfind("direct-l+", 0) == 0;
  const nlopt::algorithm local =
      s.algorithm == "direct-l+cobyla" ? nlopt::LN_COBYLA : nlopt::LN_SBPLX;
  const bool global = s.algorithm == "direct-l" || s.algorithm == "isres";
  // u of the best point (by the barrier value) evaluated so far in combination c.
  auto best_of = [&](size_t c) {
    std::vector<double> best_u = start;
    double best_value = std::numeric_limits<double>::infinity();
    for (const auto& t : result.trials) {
      if (t.combination != c) continue;
      const double v = barrier_value(t.outcome, s.budget_ms);
      if (v < best_value) {
        best_value = v;
        best_u.clear();
        for (size_t k = 0; k < d; ++k)
          best_u.push_back(
              space.encode(k, t.overrides[space.numeric[k]->spec->name].get<double>()));
      }
    }
    return best_u;
  };
  for (size_t c = 0; c < K; ++c) {
    CombinationSearch cs(space, s, evaluate, result, cache, c);
    int left = share[c];
    try {
      if (hybrid) {
        // Global first (DIRECT-L, Gablonsky & Kelley 2001: divides the box where the value is low
        // or the box is large), half of the share; then a local search from the best point so
        // far (Rowan's Subplex on the barrier, or Powell's COBYLA with the budget as a linear-
        // approximated constraint), with restarts from Halton points while evaluations remain.
        left -= cs.run(nlopt::GN_DIRECT_L, start, share[c] / 2, 0.0, false);
        const std::vector<double> best_u = best_of(c);
        left -= cs.run(local, best_u, left, 0.1, local == nlopt::LN_COBYLA);
      } else {
        left -= cs.run(single.at(s.algorithm), start, left, 0.25, constrained);
      }
      // A local search that converged with evaluations left restarts: the hybrids from the best
      // point so far with a smaller first step (the optimum under a budget lies on the budget's
      // edge, where a simplex shrinks early), then from Halton points once that finds nothing new;
      // the plain local searches from Halton points.
      bool near = hybrid;
      for (uint64_t restart = 1; left > 0 && !global && restart <= 64; ++restart) {
        std::vector<double> u(d);
        for (size_t k = 0; k < d; ++k) u[k] = halton(restart + 7 * c, kPrimes[k % 16]);
        const nlopt::algorithm a = hybrid ? local : single.at(s.algorithm);
        const int found = cs.run(a, near ? best_of(c) : u, left,
                                 near ? 0.1 / static_cast<double>(restart + 1) : 0.25,
                                 constrained || a == nlopt::LN_COBYLA);
        left -= found;
        if (near && found == 0) near = false;
      }
    } catch (const SearchStopped&) {
      result.stopped = true;
      break;
    }
  }
  return finish();
}

}  // namespace aoeval
