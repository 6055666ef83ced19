// The temporal estimators' claims (issue 31), answered as figures with checks: `gtao-temporal`
// (Jimenez et al. 2016 §5.2: 1 slice with 6 rotations, accumulated, against 6 slices per frame, by
// frame, and the per-frame cost of each), `temporal-equal-time` (rtao, raytraced and gtao-cpu with
// its temporal stage at rtao's per-frame time on a sequence with disocclusions, scored by
// steady_rmse_excess, temporal_rmse_excess and settle_frames side by side), `rtao-convergence`
// (rmse_excess by frame of rtao at 1 ray per pixel, with and without its a-trous passes, against
// raytraced at 1, 4, 16 and 64 rays per frame without accumulation, on a static camera; and how
// many frames rtao takes to settle after a disocclusion, on the dragon crossing the floor). The
// checks are functions of the numbers, so that a test can feed them numbers on both sides of each
// rule (figures_temporal_test.cpp).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "harness/figures/figure.h"

namespace aoeval::figures {

struct ConvergenceNumbers {
  std::vector<double> rtao, rtao_no_atrous;          // rmse_excess by frame, static camera
  std::map<int, std::vector<double>> raytraced;      // rays per frame -> rmse_excess by frame
  double rtao_steady = 0.0, no_atrous_steady = 0.0;  // steady_rmse_excess
  double settle_frames = 0.0;  // rtao on the disocclusion sequence; NaN when blank (never settled)
  int settle_sequence_frames = 0;  // that sequence's length
};
// The first frame from which `curve` stays at or below `level`; -1 when it never does.
int first_frame_staying_below(const std::vector<double>& curve, double level);
// The rms of a by-frame curve over its last half (steady_rmse_excess's frames).
double steady_of(const std::vector<double>& curve);
std::vector<Check> rtao_convergence_checks(const ConvergenceNumbers& n);
// gtao-temporal: rmse_excess by frame on a static camera of gtao-cpu with 1 slice, the paper's 6
// rotations and the shared temporal stage, and of 6 slices per frame; their per-frame times.
struct GtaoTemporalNumbers {
  std::vector<double> accumulated, six_slices;       // rmse_excess by frame
  double accumulated_ms = 0.0, six_slices_ms = 0.0;  // median per-frame time
};
// How close "approaches" must come: the accumulated steady error within this factor of 6 slices'.
inline constexpr double kApproachFactor = 1.25;
std::vector<Check> gtao_temporal_checks(const GtaoTemporalNumbers& n);

// temporal-equal-time: contenders at rtao's per-frame time on one sequence, each scored by the
// three questions (steady_rmse_excess, temporal_rmse_excess, settle_frames; NaN = blank).
struct EqualTimeContender {
  std::string name;  // "rtao", "raytraced rays:8", ...
  double steady = 0.0, flicker = 0.0, settle = 0.0, ms = 0.0;
};
struct TemporalEqualTimeNumbers {
  double budget_ms = 0.0;
  std::vector<EqualTimeContender> contenders;
};
// The winner of one question: the least value, NaN (never settled) last; "" when none has a value.
std::string winner_by(const std::vector<EqualTimeContender>& c, double EqualTimeContender::*key);
std::vector<Check> temporal_equal_time_checks(const TemporalEqualTimeNumbers& n);

// The settle bound of the third check: rtao's history limit and a-trous passes should make a
// disoccluded pixel as good as the steady state within this many frames.
inline constexpr int kSettleFramesBound = 8;

}  // namespace aoeval::figures
