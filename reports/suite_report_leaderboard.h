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
// An id fragment: letters, digits and '-' only ("mosaic-" + slug(run name) anchors a mosaic).
std::string slug(const std::string& s);

}  // namespace aoeval
