#include "harness/bench/bench_rows.h"

#include <algorithm>
#include <cstdio>

#include "base/summary.h"
#include "base/version.h"
#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {

PassTimes pass_medians(const std::vector<PassTimes>& runs) {
  std::map<std::string, std::vector<double>> values;
  for (const auto& run : runs)
    for (const auto& [pass, ms] : run) values[pass].push_back(ms);
  PassTimes out;
  for (const auto& [pass, v] : values) out[pass] = median(v);
  return out;
}

double pass_ms(const PassTimes& times, const std::string& pass) {
  const auto it = times.find(pass);
  return it == times.end() ? 0.0 : it->second;
}

std::string format_number(const char* printf_format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), printf_format, value);
  return buf;
}

ResultRow timing_row(const RunContext& context, const EstimatorInfo& estimator,
                     const ParamSet& params, const nlohmann::json& overrides,
                     const std::string& scene, const std::string& view, int width, int height,
                     const std::vector<double>& totals_ms, const PassTimes& passes,
                     const std::string& device) {
  ResultRow row;
  row.run_name = run_name(estimator, params, overrides, scene, view, width, height);
  row.estimator = estimator.name;
  row.params = params.json();
  row.scene = scene;
  row.view = view;
  row.width = width;
  row.height = height;
  row.definition = estimator.definition(params).to_json().dump();
  row.backend = backend_name(estimator.backend);
  row.set_times(totals_ms);
  for (const auto& [pass, ms] : passes)
    if (pass != "total_ms") row.pass_ms[pass] = ms;
  row.device = device;
  row.aoeval_version = kAoevalVersion;
  row.estimator_version = estimator_code_version(estimator);
  row.timestamp = context.started;
  row.status = "timing only";
  return row;
}

}  // namespace aoeval
