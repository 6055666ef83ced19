// The leaderboard at the top of the suite report: estimators (each featured configuration) by
// scenes, with rmse_excess and the median time of each featured point, the best per scene view
// marked, skipped rows marked, each value linking to its mosaic; sortable by report.js. Internal to
// reports/suite_report.
#pragma once

#include <string>
#include <vector>

#include "harness/results/suite_record.h"
#include "reports/html.h"

namespace aoeval {

// The table's HTML over the featured entries (in their order); "" when there are none.
Html leaderboard_html(const std::vector<SuiteReportEntry>& entries,
                      const std::vector<std::string>& scenes);

// The parameters set explicitly, as in the run name: "rays:16" ("defaults" when none).
std::string params_of(const ResultRow& row);
// The score every cross-estimator table and chart of the report ranks on (one truth, CONTRACT §3):
// the row's true rmse_excess (against the unbounded cosine reference every estimator of a scene
// view shares), for a sequence point its true steady_rmse_excess; NaN for a skipped row or a
// missing key. matched_score: the same key against the row's matched reference (shown beside it).
double true_score(const ResultRow& row);
double matched_score(const ResultRow& row);
// The key both read: "steady_rmse_excess" for a sequence point, else "rmse_excess".
std::string ranked_key(const ResultRow& row);
// An id fragment: letters, digits and '-' only ("mosaic-" + slug(run name) anchors a mosaic).
std::string slug(const std::string& s);

}  // namespace aoeval
