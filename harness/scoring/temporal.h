// The scores of a sequence (CONTRACT §10), over compared pixels, estimate and reference of the same
// frame, frames added in order. With r_k the rmse_excess of frame k (metrics.h's definition):
//   seq_frames                F
//   seq_reference_frames      the frames whose reference was traced for them: F less those whose
//                             reference is frame k - 1's (a static camera over a static scene is
//                             traced once: 1); how many independent reference images the keys
//                             below pool, which their precision depends on (README, "How precise
//                             a reference must be")
//   seq_rmse_excess           sqrt(mean_k r_k^2)
//   steady_rmse_excess        the same over the last half of the frames, k >= floor(F / 2)
//   seq_rmse_excess_sd, steady_rmse_excess_sd, temporal_rmse_excess_sd
//                             the standard deviation of the key from the references' noise
//                             (metrics.h's rmse_excess_sd rule): frame k's r_k^2 has variance V_k;
//                             the frames' mean, sum over runs of frames sharing one reference of
//                             (sum of sqrt(V_k))^2, over F^2 (a shared reference's noise is the
//                             same in each of its frames: fully correlated, an upper bound;
//                             independent references add); temporal_rmse_excess from its pixel
//                             pairs' d and noise terms, plus the covariance of neighbouring pairs
//                             along a trajectory (they share frame k - 1's reference), 0 where
//                             every reference repeats
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
//   settle_frames             over trajectories (below) that stay visible from age 0 through
//                             age 12 and whose reference stays within 0.02 + 3 sqrt(se_g^2 +
//                             se_12^2) of its age-12 value at every age g (the truth holds still):
//                             the smallest age g in 0..8 whose rmse_excess over those trajectories
//                             at age g is <= 1.1 x the rmse_excess of the same trajectories pooled
//                             over ages 9..12, and 9 if none; null when no trajectory qualifies
//   disocclusion_rmse_excess  rmse_excess over the pixels of age 0..3 (disoccluded within the last
//                             4 frames); null when there are none
//   lag_rmse_excess           rmse_excess over the pixels of frames k >= 4 whose point was
//                             visible (compared, not disoccluded) in every frame k - 4 .. k and
//                             whose reference changed along the trajectory from frame k - 4 to k by
//                             more than 0.05 + 3 sqrt(se_k^2 + se_{k-4}^2): the truth moved under a
//                             surface that stayed in view (where a history lags); null when none
// Trajectories (CONTRACT §10): a pixel of frame k follows its point back to the nearest pixel of
// frame k - 1 at p - motion (floor of the position less frame k - 1's jitter); its age is the
// frames since it was last disoccluded (0 in the frame that disoccludes it; frame 0's pixels and
// those whose chain leaves the image or the compared pixels have none). A trajectory is named by
// its last pixel and traced back through the kept frames, so the same point of an earlier frame may
// belong to several trajectories (magnification), each counted once.
// Maps (for the report's "where", CONTRACT §10): per pixel of the image (screen space: frame k's
// pixel p, whatever point it shows), over the frames where p counted in a key:
//   flicker map               rms of d over the frames k >= 1 where p entered temporal_rmse
//   lag map                   sqrt(max(0, mean(err^2 - stderr^2))) over the frames where p entered
//                             lag_rmse_excess (the truth moved under it: a history's trail)
// NaN where p never counted.
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
  // rmse_excess by age 0..12 over the trajectories settle_frames pools (empty when none).
  std::map<int, double> settle_excess_by_age() const;

  // The maps above, width x height floats in row order (empty before the first frame).
  std::vector<float> flicker_map() const;
  std::vector<float> lag_map() const;

  static constexpr int kSettleAge = 12;  // trajectories followed from age 0 through this age
  static constexpr int kLagFrames = 4;   // lag_rmse_excess looks back this many frames

 private:
  struct Sums {
    double n = 0.0, err2 = 0.0, noise = 0.0;
    double cross = 0.0, noise2 = 0.0;  // sums of (err^2 - var) var and var^2 (metrics.h's sd)
    double excess() const;
    // The variance of excess()^2 over the reference's noise (metrics.h, rmse_excess_sd).
    double variance() const;
    void add(const Sums& o) {
      n += o.n;
      err2 += o.err2;
      noise += o.noise;
      cross += o.cross;
      noise2 += o.noise2;
    }
  };
  // Frames that share one reference (a run of ref_repeats_previous): the reference's noise n_i is
  // common to them, so the mean of their excess^2 has variance (4 sum_i dbar_i^2 s_i^2 + 2 sum_i
  // s_i^4) / N^2 with dbar_i the pixel's error averaged over the run (an error that changes sign
  // from frame to frame averages the cross term away); estimated from the observed mean error
  // ebar_i = dbar_i - n_i by ebar_i^2 - s_i^2. Runs are independent of each other.
  struct SharedRun {
    int first = 0, frames = 0;
    double variance = 0.0;  // of the run's mean excess^2 over its frames
  };
  SharedRun current_run() const;
  // The standard deviation of the rms over frames [from, F) of the frames' excess from the
  // references' noise: each run's variance weighted by its frames in range, squared (a run that
  // straddles `from` keeps its whole-run mean error: an approximation for the steady key).
  double frames_sd(int from, double excess) const;
  // Adds this frame's trajectories that reach age kSettleAge or a visible run of kLagFrames + 1.
  void follow_trajectories(const std::vector<int>& age, const std::vector<int>& run);
  int width_ = 0, height_ = 0;
  std::vector<double> frame_excess_;
  std::vector<SharedRun> runs_;  // the finished runs of frames sharing a reference
  std::vector<double> run_err_;  // the current run: per pixel, the sum of est - ref
  std::vector<float> run_var_;   // and its reference's stderr^2
  std::vector<int> run_count_;   // and how many of the run's frames compared it
  int run_first_ = 0, run_frames_ = 0;
  int reference_frames_ = 0;  // frames with a reference of their own (seq_reference_frames)
  Sums temporal_;
  std::map<int, Sums> by_age_;
  Sums settle_[kSettleAge + 1];  // by age, over the qualifying trajectories
  Sums lag_;
  std::vector<Sums> flicker_px_, lag_px_;  // the maps' sums, per pixel
  // One kept frame, for tracing trajectories back.
  struct Kept {
    std::vector<float> ref, var;
    std::vector<double> err;
    std::vector<int> prev;  // the nearest pixel of the frame before (-1: none, not compared)
  };
  std::vector<Kept> kept_;     // the last kSettleAge + 1 frames, oldest first
  std::vector<int> prev_run_;  // frames the point has stayed visible, not disoccluded, up to k - 1
  // Frame k - 1, kept for the next frame's reads.
  std::vector<float> prev_est_, prev_ref_, prev_var_;
  std::vector<double> prev_pair_d_;  // frame k - 1's d per pixel (NaN: none), for the covariance
  double temporal_pair_cov_ = 0.0;   // sum of the neighbouring pairs' covariance estimates
  std::vector<uint8_t> prev_compared_;
  std::vector<int> prev_age_;  // -1: never disoccluded
};

}  // namespace aoeval
