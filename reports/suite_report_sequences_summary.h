// The summary that opens the report's "Sequences" part (CONTRACT §10), over every sequence point
// at once, and each point's maps of where it flickers and lags. Reads what the runner kept
// (harness/sweep/kept_sequence.h: sequence.json, maps.exr); runs nothing. Internal to
// reports/suite_report_sequences.
//   table    one row per sequence point, the leaderboard's style (sortable by report.js): ranked
//            within each scene view on the one truth, true steady_rmse_excess (suite_report_
//            leaderboard.h, true_score), with the matched steady_rmse_excess and the true
//            temporal_rmse_excess, lag_rmse_excess, disocclusion_rmse_excess, converge_frames,
//            settle_frames and ms beside it; each estimator links to its point's section
//   overlay  per scene view of a sequence, one chart (one axes, one y scale) of true_rmse_excess
//            by frame of each of its points (rmse_excess against the matched reference when an
//            older manifest lacks the true one)
//   maps     per point, flicker | lag (maps.exr) through inferno, each on its own scale, inside
//            the viewer (kind "maps": zoom, probe values)
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "drawing/plot.h"
#include "harness/results/result_row.h"
#include "reports/html.h"

namespace aoeval {

// A sequence point as the report reads it: its row, its manifest and its folder (relative to the
// output folder).
struct SequencePoint {
  const ResultRow* row = nullptr;
  nlohmann::json manifest;
  std::string dir;
};

// The sortable table of every point; "" when there are none.
Html sequence_summary_table(const std::vector<SequencePoint>& points);

// One overlay chart per scene view (written to <out>/<plots_rel>/, appended to `plots` for the
// caller to render when not up to date) and the figures' HTML.
Html sequence_overlay_charts(const std::string& out_dir, const std::string& plots_rel,
                             const std::vector<SequencePoint>& points,
                             std::vector<std::pair<PlotSpec, std::string>>& plots);

// The point's flicker | lag figure inside its viewer; "" when its manifest names no maps.exr.
// InputError naming the file when maps.exr cannot be read.
Html sequence_maps_figure(const std::string& out_dir, const SequencePoint& point);

}  // namespace aoeval
