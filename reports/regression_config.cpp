#include "reports/regression_config.h"

#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/json_reader.h"

namespace aoeval {

namespace {

// The rule of a "<key>_relative" / "_sigmas" / "_absolute" config key, for the tracked keys of
// Thresholds::metrics; nullptr when `name` is not one.
double* rule_field(const std::string& name, Thresholds& t) {
  for (const std::string& key : rule_metric_keys()) {
    if (name.size() <= key.size() + 1 || name.compare(0, key.size() + 1, key + "_") != 0) continue;
    const std::string part = name.substr(key.size() + 1);
    auto it = t.metrics.find(key);
    if (it == t.metrics.end()) it = t.metrics.emplace(key, MetricRule{}).first;
    if (part == "relative") return &it->second.relative;
    if (part == "sigmas") return &it->second.sigmas;
    if (part == "absolute") return &it->second.absolute;
  }
  return nullptr;
}

std::string known_keys() {
  std::string known =
      "rmse_excess_relative, rmse_excess_sigmas, rmse_excess_absolute, bias_relative, "
      "bias_sigmas, bias_absolute, bent_relative, bent_sigmas, bent_absolute, time_relative, "
      "time_alpha, change_mean_shift, change_action, missing";
  for (const std::string& key : rule_metric_keys())
    known += ", " + key + "_relative, " + key + "_sigmas, " + key + "_absolute";
  return known;
}

// Overlays the keys of `j` onto `t`; `where` names the file and the object for error messages.
void apply(const nlohmann::json& j, Thresholds& t, const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": expected an object of thresholds");
  for (const auto& [key, value] : j.items()) {
    const std::string at = where + "." + key;
    if (key == "missing") {
      if (!value.is_string() || (value != "fail" && value != "warn"))
        throw InputError(at + ": expected \"fail\" or \"warn\"");
      t.missing_fails = value == "fail";
      continue;
    }
    if (key == "change_action") {
      if (!value.is_string() || (value != "fail" && value != "warn"))
        throw InputError(at + ": expected \"fail\" or \"warn\"");
      t.change_fails = value == "fail";
      continue;
    }
    double* field = key == "rmse_excess_relative"   ? &t.rmse_excess_relative
                    : key == "rmse_excess_sigmas"   ? &t.rmse_excess_sigmas
                    : key == "rmse_excess_absolute" ? &t.rmse_excess_absolute
                    : key == "bias_relative"        ? &t.bias_relative
                    : key == "bias_sigmas"          ? &t.bias_sigmas
                    : key == "bias_absolute"        ? &t.bias_absolute
                    : key == "bent_relative"        ? &t.bent_relative
                    : key == "bent_sigmas"          ? &t.bent_sigmas
                    : key == "bent_absolute"        ? &t.bent_absolute
                    : key == "time_relative"        ? &t.time_relative
                    : key == "time_alpha"           ? &t.time_alpha
                    : key == "change_mean_shift"    ? &t.change_mean_shift
                                                    : rule_field(key, t);
    if (!field) throw InputError(at + ": unknown key (known: " + known_keys() + ")");
    if (!value.is_number() || value.get<double>() < 0.0)
      throw InputError(at + ": expected a number >= 0");
    if (key == "time_alpha" && (value.get<double>() <= 0.0 || value.get<double>() >= 1.0))
      throw InputError(at + ": expected a level in (0, 1)");
    *field = value.get<double>();
  }
}

std::map<std::string, nlohmann::json> overrides(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": expected an object keyed by name");
  std::map<std::string, nlohmann::json> out;
  for (const auto& [name, value] : j.items()) {
    Thresholds probe;
    apply(value, probe, where + "." + name);  // validated now, not when a row first needs it
    out[name] = value;
  }
  return out;
}

}  // namespace

RegressionConfig RegressionConfig::parse(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": expected a JSON object");
  RegressionConfig c;
  c.source_ = where;
  for (const auto& [key, value] : j.items()) {
    if (key == "defaults") {
      apply(value, c.defaults_, where + ": defaults");
    } else if (key == "scenes") {
      c.scenes_ = overrides(value, where + ": scenes");
    } else if (key == "estimators") {
      c.estimators_ = overrides(value, where + ": estimators");
    } else if (key != "comment") {
      throw InputError(where + ": unknown key \"" + key +
                       "\" (known: defaults, scenes, estimators, comment)");
    }
  }
  return c;
}

RegressionConfig RegressionConfig::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the dashboard thresholds file");
  std::stringstream text;
  text << in.rdbuf();
  return parse(parse_json_text(text.str(), path), path);
}

Thresholds RegressionConfig::thresholds(const std::string& estimator,
                                        const std::string& scene) const {
  Thresholds t = defaults_;
  if (const auto it = scenes_.find(scene); it != scenes_.end())
    apply(it->second, t, source_ + ": scenes." + scene);
  if (const auto it = estimators_.find(estimator); it != estimators_.end())
    apply(it->second, t, source_ + ": estimators." + estimator);
  return t;
}

std::string default_regression_config_path() {
  return std::string(AOEVAL_SOURCE_DIR) + "/reports/dashboard.json";
}

}  // namespace aoeval
