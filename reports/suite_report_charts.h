// The suite report's error-against-time charts (reports/plot.h, matplotlib): one per estimator,
// one series per scene view, each series' Pareto front marked. Internal to reports/suite_report.
#pragma once

#include <string>
#include <vector>

#include "reports/suite_report.h"

namespace aoeval {

struct EstimatorChart {
  std::string estimator;
  std::string png;     // relative to the output folder; "" when no row of it ran ("skipped")
  std::string metric;  // the error on the y axis: "rmse_excess"
  std::vector<const SuiteReportEntry*> rows;  // every row of the estimator, in run order
  std::vector<bool> on_front;                 // per row: on its series' Pareto front
  std::vector<std::string> swept;             // the parameters that vary over its rows (title);
                                              // Pareto points are labelled with their series' own
};

// The error every chart plots, against time_ms_median on a log axis: rmse_excess against true AO
// (the RMSE with the reference's own noise removed, CONTRACT §4), the one truth the leaderboard
// ranks on (suite_report_leaderboard.h, true_score: a sequence point's true steady_rmse_excess),
// so that points of one chart whose parameters change the AO definition (dmax) share a truth.
inline constexpr const char* kChartMetric = "true rmse_excess";

// Renders every estimator's chart into <out_dir>/runs/<run_id>/plots/ (two python processes at a
// time) and returns them in order of the estimators' first rows.
std::vector<EstimatorChart> write_estimator_charts(const std::string& out_dir,
                                                   const SuiteReport& report);

}  // namespace aoeval
