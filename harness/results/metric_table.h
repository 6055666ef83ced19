// The one table of metrics (CONTRACT §4 "Metrics", §10's sequence keys): every key a results row
// can carry, once, with what it means and how the rest of aoeval treats it. Scoring names its keys
// from it (scoring/metrics.h metric_keys(), bent_metrics.h, temporal.h), rows take their metric
// columns from it (result_row.h), tune its objectives and their direction (tune_spec.cpp), the
// suite report its metrics table (reports/suite_report.cpp) and the dashboard the keys it judges
// (reports/regression.cpp, dashboard_history.cpp). metric_table_test checks that every key a
// scorer writes has a row here and every row is written by its scorer, so a metric added in one
// place and forgotten in another fails a test instead of silently missing a column.
//
// Adding a metric: a row here, its value in the scoring function of its family, and its test.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

// Which scorer writes the key: compare_images (every row), the bent-normal comparison (rows whose
// estimate has bent normals; blank otherwise), the sequence scorer (sequence views; blank for a
// still view).
enum class MetricFamily { image, bent, sequence };

// Which way is better. `none`: not a measure of error (a count of pixels or frames, the
// reference's own noise, a signed mean whose least value is not its best).
enum class Better { lower, higher, none };

struct MetricDef {
  std::string key;
  MetricFamily family = MetricFamily::image;
  Better better = Better::lower;
  // Shown in the suite report's metrics table: against the matched reference, and against true
  // AO (the "true_" column).
  bool report_matched = false, report_true = false;
  // Judged by the dashboard (CONTRACT §12): a REGRESSED/IMPROVED check and a history series.
  // reports/regression.h judges every flagged key (its thresholds: Thresholds::rule); a flagged
  // key a row lacks (a still view's sequence keys) is not judged on that row.
  bool dashboard = false;
  std::string meaning;  // one line, with its unit
};

// Every metric, in column order (image keys, then bent, then sequence).
const std::vector<MetricDef>& metric_table();
// The keys of one family, in column order.
std::vector<std::string> metric_keys_of(MetricFamily family);
// Every key, in column order (the results' metric columns; "true_" + each follows them).
const std::vector<std::string>& all_metric_keys();
// The row of `key` ("true_" before it is accepted and ignored), or nullptr.
const MetricDef* find_metric(const std::string& key);
// The keys a tune may minimise or maximise (Better is not none), in column order.
std::vector<std::string> objective_metric_keys();
// The keys the dashboard judges, in column order.
std::vector<std::string> dashboard_metric_keys();

}  // namespace aoeval
