#include "harness/tune/tune_spec.h"

#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "base/json_reader.h"
#include "estimators/plugins/plugin_registry.h"
#include "estimators/registry.h"
#include "harness/results/metric_table.h"
#include "scenes/corpus.h"

namespace aoeval {

namespace {

bool contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

std::string joined(const std::vector<std::string>& list) {
  std::string out;
  for (const auto& s : list) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "literal" + a temporary.
std::string range_text(double lo, double hi) {
  std::string text = "[";
  text += format_param_value(lo);
  text += ", ";
  text += format_param_value(hi);
  text += "]";
  return text;
}

// One entry of tune.params, checked against the declaration `p`.
TuneParam parse_param(const EstimatorInfo& e, const ParamSpec& p, const nlohmann::json& entry,
                      const JsonReader& tune) {
  const std::string key = "params." + p.name;
  TuneParam t;
  t.spec = &p;
  if (p.type == ParamType::real || p.type == ParamType::integer) {
    if (!entry.is_array() || entry.size() != 2 || !entry[0].is_number() || !entry[1].is_number())
      tune.fail(key, "expected [lo, hi]");
    t.lo = entry[0].get<double>();
    t.hi = entry[1].get<double>();
    if (!(t.lo < t.hi)) tune.fail(key, "expected lo < hi (a single value belongs in \"fixed\")");
    if (p.type == ParamType::integer && (t.lo != std::floor(t.lo) || t.hi != std::floor(t.hi)))
      tune.fail(key, "an integer parameter takes integer bounds");
    if (t.lo < p.min || t.hi > p.max)
      tune.fail(key, "range " + range_text(t.lo, t.hi) + " lies outside the declared range " +
                         range_text(p.min, p.max) + " of " + e.name + "'s " + p.name);
    t.log_scale = p.log_scale;
    if (t.log_scale && !(t.lo > 0.0))
      tune.fail(key, "is declared log-scale; its range needs a positive lower bound");
    return t;
  }
  const bool all = entry.is_string() && entry.get<std::string>() == "all";
  if (p.type == ParamType::boolean) {
    if (all) {
      t.values = {false, true};
    } else {
      if (!entry.is_array() || entry.empty()) tune.fail(key, "expected \"all\" or [false, true]");
      for (const auto& v : entry) {
        if (!v.is_boolean()) tune.fail(key, "expected booleans");
        if (std::find(t.values.begin(), t.values.end(), v) == t.values.end()) t.values.push_back(v);
      }
    }
  } else {
    if (all) {
      for (const auto& c : p.choices) t.values.push_back(c);
    } else {
      if (!entry.is_array() || entry.empty())
        tune.fail(key, "expected \"all\" or a list of " + joined(p.choices));
      for (const auto& v : entry) {
        if (!v.is_string() || !contains(p.choices, v.get<std::string>()))
          tune.fail(key, std::string(1, '\'') + (v.is_string() ? v.get<std::string>() : v.dump()) +
                             "' is not one of " + joined(p.choices));
        if (std::find(t.values.begin(), t.values.end(), v) == t.values.end()) t.values.push_back(v);
      }
    }
  }
  return t;
}

}  // namespace

// The objectives are the metric table's error measures (harness/results/metric_table.h: a key whose
// Better is none, a count of pixels or frames, the reference's own noise or the signed bias, is
// not one), still-view keys first, then the sequence keys.
const std::vector<std::string>& tune_algorithms() {
  static const std::vector<std::string> names = {
      kDefaultTuneAlgorithm, "direct-l+cobyla", "direct-l", "sbplx", "bobyqa", "cobyla", "isres"};
  return names;
}

std::vector<std::string> tune_objective_keys() {
  std::vector<std::string> keys;
  for (const auto& k : objective_metric_keys())
    if (find_metric(k)->family != MetricFamily::sequence) keys.push_back(k);
  for (const auto& k : tune_sequence_objective_keys()) keys.push_back(k);
  return keys;
}

std::vector<std::string> tune_sequence_objective_keys() {
  std::vector<std::string> keys;
  for (const auto& k : objective_metric_keys())
    if (find_metric(k)->family == MetricFamily::sequence) keys.push_back(k);
  return keys;
}

TuneSpec parse_tune_spec(const nlohmann::json& doc, const std::string& file,
                         const EstimatorLookup& lookup) {
  if (!doc.is_object()) throw InputError(file + ": expected a JSON object");
  if (doc.contains("runs"))
    throw InputError(file + ": runs: a tune spec has no runs; it names its estimator in tune");
  if (!doc.contains("tune")) throw InputError(file + ": tune: missing");
  TuneSpec spec;
  spec.document = doc;

  // The sweep fields (name, scenes, views, res, reference, timing) are read by the sweep parser,
  // with any estimator as its one run: the tune's estimator, which the lookup may know where the
  // registry does not, replaces it below.
  nlohmann::json sweep_doc = doc;
  sweep_doc.erase("tune");
  sweep_doc["runs"] = nlohmann::json::array({{{"estimator", "constant"}}});
  spec.sweep = parse_sweep_spec(sweep_doc, file);
  spec.name = spec.sweep.name;

  JsonReader tune(doc.at("tune"), file, "tune");
  if (!doc.at("tune").is_object()) throw InputError(file + ": tune: expected an object");
  const std::string estimator = tune.string("estimator");
  try {
    spec.estimator = lookup ? &lookup(estimator) : &find_estimator(estimator);
    prepare_plugin_for_run(*spec.estimator);  // a shader's compile error: exit 2, nothing written
  } catch (const InputError& e) {
    tune.fail("estimator", e.what());
  }
  const EstimatorInfo& e = *spec.estimator;

  if (tune.has("fixed")) {
    const auto& f = tune.raw("fixed");
    if (!f.is_object()) tune.fail("fixed", "expected an object of parameter values");
    spec.fixed = f;
  }
  resolve_params(e.name, e.params, spec.fixed, file + ": " + tune.where("fixed"));

  const auto& params = tune.raw("params");
  if (!params.is_object() || params.empty())
    tune.fail("params", "expected an object of parameter ranges, at least one");
  std::vector<std::string> known;
  for (const auto& p : e.params) known.push_back(p.name);
  for (auto it = params.begin(); it != params.end(); ++it) {
    if (!e.find_param(it.key()))
      tune.fail("params." + it.key(),
                "unknown parameter of " + e.name + " (known: " + joined(known) + ")");
    if (spec.fixed.contains(it.key()))
      tune.fail("params." + it.key(), "is in both params and fixed");
    // Common random numbers: every point runs with the same seed, so that the differences the
    // optimiser sees come from the parameters, not from a new draw of the estimator's noise.
    if (it.key() == "seed")
      tune.fail("params.seed",
                "the seed is held fixed so that every point sees the same random numbers; set "
                "it in fixed");
  }
  for (const auto& p : e.params)  // declaration order, as run names and grids use
    if (params.contains(p.name)) spec.params.push_back(parse_param(e, p, params[p.name], tune));

  // The objective is one key or a sum of keys, "lag_rmse_excess+steady_rmse_excess": each term
  // is scored per view as a single key would be, and the sum is the point's value per view.
  spec.objective = tune.string("objective", "rmse_excess");
  for (size_t at = 0;;) {
    const size_t plus = spec.objective.find('+', at);
    spec.objective_terms.push_back(spec.objective.substr(at, plus - at));
    if (plus == std::string::npos) break;
    at = plus + 1;
  }
  const bool sum = spec.objective_terms.size() > 1;
  for (const std::string& term : spec.objective_terms) {
    const std::string bare = term.rfind("true_", 0) == 0 ? term.substr(5) : term;
    if (!contains(tune_objective_keys(), bare)) {
      if (find_metric(bare))
        tune.fail("objective", "'" + term + "' is not an error measure; use one of " +
                                   joined(tune_objective_keys()));
      tune.fail("objective", "'" + term + "' is not a metric key; use one of " +
                                 joined(tune_objective_keys()) + " (or true_ before one)" +
                                 (sum ? ", or a sum of them joined by +" : ""));
    }
    const bool higher = find_metric(bare)->better == Better::higher;
    if (sum && higher)
      tune.fail("objective", "'" + term + "' grows with quality: a sum adds errors to minimise");
    if (std::count(spec.objective_terms.begin(), spec.objective_terms.end(), term) > 1)
      tune.fail("objective", "'" + term + "' appears twice in the sum");
    spec.maximise = higher;
    spec.sequence_objective =
        spec.sequence_objective || contains(tune_sequence_objective_keys(), bare);
  }
  spec.budget_ms = tune.has("budget_ms") ? tune.number("budget_ms", 1e-6, 1e9) : 0.0;
  spec.evaluations =
      static_cast<int>(tune.integer("evaluations", kDefaultTuneEvaluations, 1, 100000));
  if (auto o = tune.optional_object("optimiser")) {
    spec.algorithm = o->choice("algorithm", spec.algorithm, tune_algorithms());
    spec.seed = static_cast<uint64_t>(o->integer("seed", kDefaultTuneSeed, 0, INT64_MAX));
    o->finish();
  }
  tune.finish();

  spec.sweep.runs.clear();
  SweepSpec::Run run;
  run.estimator = spec.estimator;
  run.fixed = spec.fixed;
  spec.sweep.runs.push_back(run);

  // A sequence score exists only on a sequence view's row (CONTRACT §10): every view the tune
  // evaluates must be one ("views": "all" takes the still views only, so it names none).
  if (spec.sequence_objective) {
    for (const SweepPoint& p : expand_sweep(spec.sweep)) {
      const std::vector<View> views = load_scene_views(resolve_scene_path(p.scene));
      for (const View& v : views)
        if (v.name == p.view && !v.sequence)
          throw InputError(file + ": tune.objective: '" + spec.objective +
                           "' is a sequence score (CONTRACT §10) but view '" + p.view +
                           "' of scene " + p.scene +
                           " is a still view; name sequence views in \"views\" (e.g. "
                           "[\"orbit\"] of bunny)");
    }
  }
  return spec;
}

TuneSpec load_tune_spec(const std::string& path, const EstimatorLookup& lookup) {
  return parse_tune_spec(parse_json_file(path), path, lookup);
}

}  // namespace aoeval
