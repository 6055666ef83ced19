// What every `aoeval bench` writes alike: a results row per timed configuration (status "timing
// only": no accuracy columns), and the per-pass medians it carries.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimators/registry.h"
#include "harness/results/result_row.h"
#include "harness/results/results_store.h"

namespace aoeval {

// Pass name -> milliseconds, as EstimateResult::pass_ms and GPU timers report them.
using PassTimes = std::map<std::string, double>;

// The median per pass over repetitions (a pass missing from some repetitions: over those it has).
PassTimes pass_medians(const std::vector<PassTimes>& runs);

// times.at(pass), or 0 where the pass did not run.
double pass_ms(const PassTimes& times, const std::string& pass);

// printf of one number, for tables.
std::string format_number(const char* printf_format, double value);

// The row of one timed configuration: median/min/max and the samples of `totals_ms`, the passes'
// medians (total_ms excluded: it is the row's time), `device` (the CPU's: "", filled in when the
// row is recorded), and the run's start as its timestamp. RunRecorder::record (run_recorder.h)
// stamps the run's identity (run_id, machine, git_commit) on it.
ResultRow timing_row(const RunContext& context, const EstimatorInfo& estimator,
                     const ParamSet& params, const nlohmann::json& overrides,
                     const std::string& scene, const std::string& view, int width, int height,
                     const std::vector<double>& totals_ms, const PassTimes& passes,
                     const std::string& device);

}  // namespace aoeval
