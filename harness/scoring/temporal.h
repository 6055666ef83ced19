// The scores of a sequence (CONTRACT §10), over compared pixels, estimate and reference of the same
// frame, frames added in order. With r_k the rmse_excess of frame k (metrics.h's definition):
//   seq_frames                F
//   seq_rmse_excess           sqrt(mean_k r_k^2)
//   steady_rmse_excess        the same over the last half of the frames, k >= floor(F / 2)
//   temporal_rmse             sqrt(mean d^2) over frames k >= 1 and pixels p not disoccluded, with
//                             d = (est_k(p) - est_{k-1}(p - m)) - (ref_k(p) - ref_{k-1}(p - m)),
//                             m = motion_k(p), p the pixel centre; frame k - 1 is read bilinearly
//                             from its four nearest pixel centres, over those of them compared in
//                             frame k - 1 (weights renormalised; a pixel with none is left out)
//   temporal_rmse_excess      sqrt(max(0, temporal_rmse^2 - mean(stderr_k(p)^2 + v_{k-1}))), where
//                             v_{k-1} = sum_i w_i^2 stderr_{k-1,i}^2 is the variance of the
//                             bilinear read of ref_{k-1} (= stderr_{k-1}(p - m)^2 at a pixel
//                             centre): the flicker the estimate adds beyond the reference's noise;
//                             0 instead of that sum in a frame whose reference is frame k - 1's
//                             (TemporalFrame::ref_repeats_previous: no independent noise)
//   converge_frames           the first frame k with r_j <= 1.1 steady_rmse_excess for every j >= k
//   settle_frames             pixels grouped by their age, the frames since they were last
//                             disoccluded (0 in the frame that disoccludes them, then carried
//                             along the motion from the nearest pixel of frame k - 1, plus one):
//                             the first age whose group's rmse_excess is <= 1.1 steady_rmse_excess;
//                             null when no pixel was disoccluded (or no age group gets there)
//   disocclusion_rmse_excess  rmse_excess over the pixels of age 0..3 (disoccluded within the last
//                             4 frames); null when there are none
// Keys that have no value (temporal_* of a single frame) are null. Sums are in double, pixels in
// row order, so results do not depend on threads.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace aoeval {

struct TemporalFrame {
  int width = 0, height = 0;
  const float* est = nullptr;
  const float* ref = nullptr;
  const float* ref_stderr = nullptr;   // may be null (no stderr: 0)
  const uint8_t* compared = nullptr;   // 1 where the pixel is compared (both covered)
  const float* motion = nullptr;       // interleaved x, y per pixel (null: zero motion)
  const float* disoccluded = nullptr;  // 1 where disoccluded (null: none)
  float prev_jitter_x = 0.0f, prev_jitter_y = 0.0f;  // frame k - 1's sample offset (ages' lookup)
  // `ref` is frame k - 1's reference itself, not an independent trace: the frame did not change
  // (same posed geometry and camera), so it was traced once (issue 42). Then ref_k - ref_{k-1} is
  // exactly 0 and holds no reference noise, and temporal_rmse_excess removes none for this frame:
  // CONTRACT §10's stderr_k^2 + stderr_{k-1}^2 is the variance of the difference of two
  // independent references only. (Each frame's own rmse_excess still removes stderr_k^2.)
  bool ref_repeats_previous = false;
};

class TemporalScorer {
 public:
  // Adds the next frame; returns its rmse_excess. InputError when the size changes between frames.
  double add_frame(const TemporalFrame& frame);
  // The keys above, each prefixed with `prefix` ("" or "true_").
  nlohmann::json scores(const std::string& prefix = "") const;
  // The key names in their fixed order.
  static const std::vector<std::string>& keys();
  const std::vector<double>& frame_rmse_excess() const { return frame_excess_; }
  // rmse_excess by age since disocclusion (0, 1, 2, ...), for the report's chart.
  std::map<int, double> rmse_excess_by_age() const;

 private:
  struct Sums {
    double n = 0.0, err2 = 0.0, noise = 0.0;
    double excess() const;
  };
  int width_ = 0, height_ = 0;
  std::vector<double> frame_excess_;
  Sums temporal_;
  std::map<int, Sums> by_age_;
  // Frame k - 1, kept for the next frame's reads.
  std::vector<float> prev_est_, prev_ref_, prev_var_;
  std::vector<uint8_t> prev_compared_;
  std::vector<int> prev_age_;  // -1: never disoccluded
};

}  // namespace aoeval
