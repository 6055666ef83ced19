// The dashboard's thresholds file (default reports/dashboard.json): defaults, then per-scene and
// per-estimator overrides, each a JSON object of Thresholds keys:
//   {"defaults":   {"rmse_excess_relative": 0.05, "time_relative": 0.10, ...},
//    "scenes":     {"tree-apple": {"bias_absolute": 0.004}},
//    "estimators": {"hbao-split": {"time_relative": 0.20}},
//    "comment":    "free text"}
// Keys: rmse_excess_relative, rmse_excess_sigmas, rmse_excess_absolute, bias_relative,
// bias_sigmas, bias_absolute, bent_relative, bent_sigmas, bent_absolute, time_relative, time_alpha,
// change_mean_shift (numbers >= 0; alpha in (0, 1)), missing and change_action ("fail" or "warn"),
// and for every other key the metric table flags for the dashboard (the sequence keys, e.g.
// temporal_rmse_excess) "<key>_relative", "<key>_sigmas" and "<key>_absolute" (Thresholds::rule).
// For a row of estimator E on scene S the built-in defaults (regression.h) are overlaid by
// "defaults", then scenes[S], then estimators[E] (the estimator is the more specific). Unknown keys
// anywhere are errors (InputError naming the file and the key): a misspelt threshold would
// otherwise be silently ignored.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "reports/regression.h"

namespace aoeval {

class RegressionConfig {
 public:
  RegressionConfig() = default;  // the built-in defaults, no overrides
  // Reads and validates `path`; InputError on a missing file, bad JSON, unknown key or bad value.
  static RegressionConfig load(const std::string& path);
  static RegressionConfig parse(const nlohmann::json& j, const std::string& where);

  Thresholds thresholds(const std::string& estimator, const std::string& scene) const;
  const std::string& source() const { return source_; }

 private:
  Thresholds defaults_;
  std::map<std::string, nlohmann::json> scenes_, estimators_;
  std::string source_ = "built-in defaults";
};

// The thresholds file used when --config is not given: reports/dashboard.json of the source tree.
std::string default_regression_config_path();

}  // namespace aoeval
