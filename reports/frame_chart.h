// A per-frame chart of a sequence point for the dashboard (issue 46): one figure of every frame,
// the baseline run's and the new run's, as an inline SVG (no image file, no plotting process).
// The frames come from the history's frames table (results_store.h).
#pragma once

#include <string>
#include <vector>

#include "harness/results/point_record.h"
#include "reports/html.h"

namespace aoeval {

// `figure` is "time_ms" or a frame metric key ("rmse_excess"); a frame without it is left out.
// Empty when neither run has a frame with it.
Html frame_chart(const std::vector<FrameRow>& before, const std::vector<FrameRow>& after,
                 const std::string& figure);

}  // namespace aoeval
