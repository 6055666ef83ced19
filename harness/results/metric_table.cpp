#include "harness/results/metric_table.h"

#include <algorithm>

namespace aoeval {

namespace {

using F = MetricFamily;
using B = Better;

// The definitions in full are beside each scorer (scoring/metrics.h, bent_metrics.h, temporal.h);
// a meaning here is the one line a table, a help text or a report shows.
std::vector<MetricDef> build_table() {
  return {
      // CONTRACT §4: every row, over the compared pixels (both images covered).
      {.key = "pixels",
       .family = F::image,
       .better = B::none,
       .meaning = "compared pixels (covered in both images)"},
      {.key = "rmse",
       .family = F::image,
       .better = B::lower,
       .report_matched = true,
       .report_true = true,
       .meaning = "root mean square of estimate - reference (AO units)"},
      {.key = "mae",
       .family = F::image,
       .better = B::lower,
       .meaning = "mean |estimate - reference| (AO units)"},
      {.key = "bias",
       .family = F::image,
       .better = B::none,
       .report_matched = true,
       .dashboard = true,
       .meaning = "mean of estimate - reference, signed (AO units)"},
      {.key = "max_abs",
       .family = F::image,
       .better = B::lower,
       .meaning = "largest |estimate - reference| (AO units)"},
      {.key = "p95_abs",
       .family = F::image,
       .better = B::lower,
       .meaning = "95th percentile of |estimate - reference| by nearest rank (AO units)"},
      {.key = "median_abs",
       .family = F::image,
       .better = B::lower,
       .meaning = "median |estimate - reference| by nearest rank (AO units): the typical pixel"},
      {.key = "psnr",
       .family = F::image,
       .better = B::higher,
       .meaning = "10 log10(1 / mean square error), peak 1 (dB); null when identical"},
      {.key = "ssim",
       .family = F::image,
       .better = B::higher,
       .report_matched = true,
       .report_true = true,
       .meaning = "structural similarity, Wang et al. 2004 eq. 13 (1 = same)"},
      {.key = "flip_mean",
       .family = F::image,
       .better = B::lower,
       .report_matched = true,
       .meaning = "mean LDR-FLIP error of the AO images seen as grey (Andersson et al. 2020)"},
      {.key = "ref_stderr_rms",
       .family = F::image,
       .better = B::none,
       .meaning = "rms of the reference's per-pixel standard error (its own noise, AO units)"},
      {.key = "rmse_excess",
       .family = F::image,
       .better = B::lower,
       .report_matched = true,
       .dashboard = true,
       .meaning =
           "sqrt(max(0, rmse^2 - mean ref stderr^2)): the error beyond the reference's noise"},
      {.key = "rmse_excess_sd",
       .family = F::image,
       .better = B::none,
       .meaning = "standard deviation of rmse_excess from the reference's noise (what its spp "
                  "buys)"},
      // CONTRACT §4: rows whose estimate has bent normals; blank otherwise.
      {.key = "bent_pixels",
       .family = F::bent,
       .better = B::none,
       .meaning = "compared pixels where both bent normals are non-zero"},
      {.key = "bent_angle_mean",
       .family = F::bent,
       .better = B::lower,
       .report_matched = true,
       .meaning = "mean angle between estimate and reference bent normals (degrees)"},
      {.key = "bent_angle_p95",
       .family = F::bent,
       .better = B::lower,
       .report_matched = true,
       .meaning = "95th percentile of that angle by nearest rank (degrees)"},
      {.key = "bent_ref_stderr",
       .family = F::bent,
       .better = B::none,
       .meaning = "rms angular noise of the reference's bent normal (degrees)"},
      {.key = "bent_angle_excess",
       .family = F::bent,
       .better = B::lower,
       .report_matched = true,
       .dashboard = true,
       .meaning = "rms angle with the reference's bent-normal noise removed (degrees)"},
      // CONTRACT §10: sequence views; blank for a still view.
      {.key = "seq_frames",
       .family = F::sequence,
       .better = B::none,
       .meaning = "frames in the sequence"},
      {.key = "seq_reference_frames",
       .family = F::sequence,
       .better = B::none,
       .meaning = "frames with a reference traced for them (the others repeat frame k - 1's: "
                  "a static camera over a static scene is traced once); the sequence keys' "
                  "precision depends on it"},
      {.key = "seq_rmse_excess",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "rms over frames of each frame's rmse_excess"},
      {.key = "seq_rmse_excess_sd",
       .family = F::sequence,
       .better = B::none,
       .meaning = "standard deviation of seq_rmse_excess from the references' noise"},
      {.key = "steady_rmse_excess",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "the same over the last half of the frames (the steady state)"},
      {.key = "steady_rmse_excess_sd",
       .family = F::sequence,
       .better = B::none,
       .meaning = "standard deviation of steady_rmse_excess from the references' noise"},
      {.key = "temporal_rmse",
       .family = F::sequence,
       .better = B::lower,
       .meaning = "rms of the frame-to-frame change beyond the reference's, along the motion"},
      {.key = "temporal_rmse_excess",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning =
           "temporal_rmse with the references' noise removed: the flicker the estimate adds"},
      {.key = "temporal_rmse_excess_sd",
       .family = F::sequence,
       .better = B::none,
       .meaning = "standard deviation of temporal_rmse_excess from the references' noise"},
      {.key = "converge_frames",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "first frame from which every frame is within 1.1 x steady_rmse_excess"},
      {.key = "settle_frames",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "age after a disocclusion from which trajectories whose truth holds still are "
                  "within 1.1 x their error at ages 9..12 (0..8; 9 = not by age 8)"},
      {.key = "disocclusion_rmse_excess",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "rmse_excess over pixels disoccluded within the last 4 frames"},
      {.key = "lag_rmse_excess",
       .family = F::sequence,
       .better = B::lower,
       .dashboard = true,
       .meaning = "rmse_excess where the truth moved under a surface in view for 4 frames "
                  "(AO ghosting: a history that lags)"},
  };
}

}  // namespace

const std::vector<MetricDef>& metric_table() {
  static const std::vector<MetricDef> table = build_table();
  return table;
}

std::vector<std::string> metric_keys_of(MetricFamily family) {
  std::vector<std::string> keys;
  for (const MetricDef& m : metric_table())
    if (m.family == family) keys.push_back(m.key);
  return keys;
}

const std::vector<std::string>& all_metric_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k;
    for (const MetricDef& m : metric_table()) k.push_back(m.key);
    return k;
  }();
  return keys;
}

const MetricDef* find_metric(const std::string& key) {
  const std::string bare = key.rfind("true_", 0) == 0 ? key.substr(5) : key;
  const auto& t = metric_table();
  const auto it =
      std::find_if(t.begin(), t.end(), [&](const MetricDef& m) { return m.key == bare; });
  return it == t.end() ? nullptr : &*it;
}

std::vector<std::string> objective_metric_keys() {
  std::vector<std::string> keys;
  for (const MetricDef& m : metric_table())
    if (m.better != Better::none) keys.push_back(m.key);
  return keys;
}

std::vector<std::string> dashboard_metric_keys() {
  std::vector<std::string> keys;
  for (const MetricDef& m : metric_table())
    if (m.dashboard) keys.push_back(m.key);
  return keys;
}

}  // namespace aoeval
