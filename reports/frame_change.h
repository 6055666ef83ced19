// Which frames of a sequence point changed between two runs (issue 46): `aoeval dashboard` reads
// both runs' frames from the SQLite history (results_store.h, the frames table) and names the
// frame ranges whose rmse_excess against the matched reference moved, frame by frame, by more than
// the row rule's threshold (regression.h: max(rmse_excess_relative * baseline, rmse_excess_sigmas
// * sigma, rmse_excess_absolute), sigma the change's noise from the two frames' reference noise,
// accuracy_noise() with no estimate images). It says where a sequence changed; the row's verdict
// stays the row rule's. Pure: frames and thresholds in, ranges out.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "harness/results/point_record.h"
#include "reports/regression.h"

namespace aoeval {

struct FrameChange {
  std::string figure = "rmse_excess";
  int compared = 0;                        // frames present in both runs with the figure
  std::vector<std::pair<int, int>> spans;  // changed frames as [first, last] runs, ascending
  int changed = 0;                         // frames in the spans
  int largest_frame = -1;                  // the changed frame that moved most
  double largest_before = 0.0, largest_after = 0.0;
};

// Frames paired by number; nullopt when fewer than two frames are in both. `same_ref`:
// same_reference() of the two rows.
std::optional<FrameChange> frame_change(const std::vector<FrameRow>& before,
                                        const std::vector<FrameRow>& after, const Thresholds& t,
                                        bool same_ref);
// "12-31" / "3, 7-9": the spans as a reader counts them (frame numbers as stored, from 0).
std::string spans_text(const std::vector<std::pair<int, int>>& spans);

}  // namespace aoeval
