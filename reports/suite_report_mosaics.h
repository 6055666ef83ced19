// The featured points of a report and their mosaics. A suite features its runs' default points and
// the runner draws their mosaics; a sweep features none, so its report shows the points on each
// estimator's Pareto front per scene view (error against time, as the charts mark them) and draws
// their mosaics here from the kept EXRs. Internal to reports/suite_report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "harness/results/suite_record.h"

namespace aoeval {

// A copy of `report` in which, when no entry is featured, the Pareto-front entries are (and
// `sweep` is set), and every featured ok entry with an estimate and a reference EXR but no mosaic
// gets one, written under <out_dir>/runs/<run id>/mosaics/ (kept when newer than its EXRs).
SuiteReport with_featured_mosaics(const std::string& out_dir, const SuiteReport& report);

// True when `target` exists and no source is newer (a drawn image is redrawn only then).
bool up_to_date(const std::filesystem::path& target,
                const std::vector<std::filesystem::path>& sources);

}  // namespace aoeval
