// Tune specifications (CONTRACT §8): the scenes, views, resolution, reference and timing of a sweep
// (§5), and a "tune" section that names one estimator, the parameters to search with their ranges,
// the fixed ones, the objective (a metric key), the time budget and the number of evaluations.
//
//   "tune": {"estimator": "hbao-split", "params": {"R": [0.05, 1.0], "Nd": [2, 24]},
//            "fixed": {"Nn": 1}, "objective": "rmse_excess", "budget_ms": 40, "evaluations": 60,
//            "optimiser": {"algorithm": "direct-l+sbplx", "seed": 1}}
//
// Ranges must lie inside the estimator's declared ranges (its ParamSpec table: built-ins and
// plug-ins alike, both come from the registry). A real or integer parameter takes [lo, hi]; a
// choice takes a list of its choices or "all"; a boolean takes a list of true/false or "all".
// "optimiser" is optional (tune_search.h lists the algorithms).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "harness/sweep/sweep_spec.h"

namespace aoeval {

// The optimiser's defaults (CONTRACT §8), written once for the spec and the search.
inline constexpr int kDefaultTuneEvaluations = 60;
inline constexpr const char* kDefaultTuneAlgorithm = "direct-l+sbplx";
inline constexpr uint64_t kDefaultTuneSeed = 1;
// The optimisers a spec may name, kDefaultTuneAlgorithm first (tune_search.cpp maps each to NLopt).
const std::vector<std::string>& tune_algorithms();

struct TuneParam {
  const ParamSpec* spec = nullptr;
  double lo = 0.0, hi = 0.0;           // real and integer: the searched interval
  std::vector<nlohmann::json> values;  // choice and boolean: the values tried
  bool log_scale = false;              // searched in log space (the declaration's scale flag)
  bool numeric() const { return spec->type == ParamType::real || spec->type == ParamType::integer; }
};

struct TuneSpec {
  std::string name;
  SweepSpec sweep;  // scenes, views, res, reference, timing; runs[0] = the estimator with `fixed`
  const EstimatorInfo* estimator = nullptr;
  std::vector<TuneParam> params;  // declaration order
  nlohmann::json fixed = nlohmann::json::object();
  std::string objective;  // a metric key, possibly "true_"-prefixed, or a sum "a+b" of such keys
  std::vector<std::string> objective_terms;  // the objective's keys, in order (one unless a sum)
  bool maximise = false;  // ssim and psnr grow with quality; every other objective key is an error
  bool sequence_objective = false;  // a sequence score (CONTRACT §10): every view is a sequence
  double budget_ms = 0.0;           // 0 = no time budget
  int evaluations = kDefaultTuneEvaluations;  // distinct points (each over every view)
  std::string algorithm = kDefaultTuneAlgorithm;
  uint64_t seed =
      kDefaultTuneSeed;     // the optimiser's own random numbers (isres), not the estimator's
  nlohmann::json document;  // the spec as read: a re-run must be the same tune to reuse rows
};

// How a parser finds an estimator by name; the registry (built-ins and plug-ins) by default. Tests
// pass their own to tune a test-only estimator that the binary does not register.
using EstimatorLookup = std::function<const EstimatorInfo&(const std::string&)>;

// Parses and validates; InputError naming the file and the field for unknown keys, an unknown
// estimator or parameter, a range outside the declaration, a value in both params and fixed, an
// objective that is not a metric key (or not an error measure), a sum with a term that is not an
// error to minimise (ssim, psnr) or that repeats one, a seed left free.
TuneSpec parse_tune_spec(const nlohmann::json& doc, const std::string& file,
                         const EstimatorLookup& lookup = {});
TuneSpec load_tune_spec(const std::string& path, const EstimatorLookup& lookup = {});

// The objective keys a tune accepts, without the optional "true_" prefix: the still metrics (§4),
// the bent-normal metrics and the sequence scores (§10, tune_sequence_objective_keys()).
std::vector<std::string> tune_objective_keys();
// The sequence scores a tune accepts (harness/scoring/temporal.h's keys but seq_frames, the
// sequence's length): they need sequence views, whose rows alone carry them.
std::vector<std::string> tune_sequence_objective_keys();

}  // namespace aoeval
