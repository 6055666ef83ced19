// The shared temporal accumulation stage: the reference design of temporal reuse in aoeval, used
// by the built-in temporal estimators of issue 31 (rtao; gtao and gtao-cpu with `temporal`, through
// temporal_estimator.h) and the design a user's temporal plug-in (CONTRACT §10, aoeval_history) is
// compared with. One frame in, per pixel:
//
//  1. Reprojection (reverse, as in TAA and Schied et al. 2017 §4.1): the point at pixel p was at
//     q = p - motion(p) in frame k - 1 (the G-buffer's motion: the offset in pixels from where the
//     point was in frame k - 1 to where it is now, CONTRACT §10; pixel centres at i + 0.5).
//  2. History read at q over the valid history texels only: a texel of frame k - 1 is valid when
//     it was covered and on the same object as p. `history_read` = catmull-rom (the default of
//     the built-in estimators) reads the value's history with the 4x4 Catmull-Rom spline (Keys
//     1981, a = -1/2; the bicubic history read of shipped TAA, Karis 2014 "High quality temporal
//     supersampling"), which a sub-pixel offset does not low-pass as a bilinear read does, so a
//     history carried over many frames of motion stays sharp; the result is kept within the range
//     of the 2x2 texels around q (no ringing, no value outside [0, 1]). Where any of the 16 taps
//     is invalid or off screen, and for the moments and the history length, the read is bilinear
//     (scenes/bilinear_taps.h) with the weights renormalised over the valid taps. At an integer
//     offset both reads are exact.
//  3. Disocclusion reset: where the G-buffer says `disoccluded` (the point was not visible in frame
//     k - 1), where no tap is valid, at the first frame and after reset(), the pixel starts afresh:
//     its value and moments are this frame's, its history length 1.
//  4. Exponential history with a minimum blend factor (Schied et al. 2017 §4.1; Yang et al. 2009,
//     "Amortized supersampling"): with L the history length read at q (frames accumulated there,
//     bilinear like the values),
//         alpha = max(alpha_min, 1 / (L + 1)),   out = alpha x + (1 - alpha) h,
//     a running mean while 1 / (L + 1) > alpha_min, a fixed-alpha exponential average after it; the
//     stored length is min(L + 1, history_limit), so alpha never drops below 1 / (history_limit +
//     1).
//  5. Neighbourhood clamping of the reprojected history h before the blend (Salvi 2016, "An
//     excursion in temporal supersampling"; the D3D12 real-time denoised AO sample's
//     TemporalSupersampling_BlendWithCurrentFrameCS): h is clamped to mu +- max(gamma sigma,
//     clamp_sigma_min), mu and sigma the mean and standard deviation of this frame's raw values
//     over the covered pixels of the (2 clamp_radius + 1)^2 window around p (3x3 by default, as in
//     TAA). It bounds how long a stale history (a moved occluder) can last.
//  5b. Anti-lag (history confidence; the idea of A-SVGF's temporal gradient, Schied et al. 2018,
//     and of NRD REBLUR's anti-lag against a fast history, on a low-passed signal): the mean of
//     this frame's raw input over the covered pixels of the (2 antilag_radius + 1)^2 window around
//     p, xbar (its variance sigma^2 / n, sigma the window's standard deviation and n its pixel
//     count), is accumulated into a fast history of at most antilag_frames frames, reprojected
//     like the value (bilinear over valid taps, reset with it):
//         a = max(1 / (Lf + 1), 1 / antilag_frames),   f = a xbar + (1 - a) f(q),
//         Var f = a^2 sigma^2 / n + (1 - a)^2 Var f(q)    (independent frames),
//     Lf the fast length read at q, stored as min(Lf + 1, antilag_frames); antilag_frames = 1
//     makes f this frame's window mean. f is compared with the same window's mean of the slow
//     history's raw first moment (frame k - 1) read at q, hbar. Both are equally low-passed, so
//     the spatial structure cancels and what is left is the change of the truth plus noise, the
//     fast history's noise sqrt(antilag_frames) times smaller than one frame's. hbar is noisy too:
//     its variance is one frame's sigma^2 / n times the first moment's spread s read at q, kept
//     per pixel as s = alpha^2 + (1 - alpha)^2 s(q) (1 at a reset; 1 / L for a running mean of L
//     frames, alpha / (2 - alpha) at a fixed blend factor; independent frames). So the test
//     compares the change with what the noise of both could give alone (a young history is as
//     noisy as this frame: without the s term a still view's noise tripped 6.8 % of bunny's
//     pixels at frame 1). With tau = antilag sqrt(Var f + s sigma^2 / n) + antilag_min, a
//     difference d = |f - hbar| > tau (a shadow that moved under a
//     surface still in view) moves the history's low-pass towards the denoised window mean, h +=
//     (f - hbar)(1 - (tau / d)^K) with K = antilag_shift_power, while h keeps its detail, and
//     scales the history length read at q by (tau / d)^P, P = antilag_length_power (the rest
//     fades faster): the history follows within a few frames instead of lagging for
//     history_limit frames. K = 1 is soft thresholding (hbar moves to f +- tau: every change
//     keeps tau of its lag in the history); K = 2 the non-negative garrote (Breiman 1995, the
//     wavelet shrinkage of Gao 1998); a larger K takes a change well above tau nearly whole and
//     one just above it (what noise trips) little. The reference design's K = 1, P = 2; gtao's
//     and rtao's are their own (issue 43, h43n). The first moment is not shifted, so hbar still
//     shows the change at the next frame, and the test trips again until the shortened history
//     has taken it in. antilag = 0 turns it off.
//  5c. The observed spread (antilag_spread_frames > 0; A-SVGF normalises its temporal gradient by
//     the signal's own spread): sigma^2 / n counts the window's pixels as independent, which an
//     input that has been denoised spatially or whose noise pattern turns every frame (gtao's 4x4
//     denoise and `rotations`) is not: there the window mean moves from frame to frame by 2.5-4
//     times more, and the test trips on a still view. The stage keeps per pixel, reprojected like
//     the fast history, the spread the difference D = f - hbar has shown: a running mean, then an
//     exponential one over antilag_spread_frames frames, of the squared change of D from the frame
//     before halved, (D_k - D_k-1)^2 / 2 (the first-difference variance estimator of Rice 1984:
//     noise independent from frame to frame gives Var D, and a change of the truth that persists,
//     a shadow moving on, or the camera's own drift of a screen-space estimate, cancels in it and
//     so keeps tripping the test; the first frame after a reset takes D^2 itself). Once the
//     running mean is full, a frame's term is capped at 9 times the noise (3 standard errors).
//     The test's noise is then max(Var f + s sigma^2 / n, that spread), and the test waits until
//     the spread holds antilag_spread_frames frames after a reset (a history that young follows
//     a change anyway; testing it against the independent-pixel noise tripped gtao's still views
//     at frames 3-5, and the gtao-temporal figure settled at frame 6 instead of 2).
//  6. Moments for SVGF (Schied et al. 2017 §4.2): the first two moments of the raw input,
//     m1 = E[x] and m2 = E[x^2], accumulated with the same alpha but never clamped (they describe
//     the samples, not the history's value); variance = max(0, m2 - m1^2).
//
// Every constant is a parameter, declared once in temporal_params(): an estimator that uses the
// stage appends that fragment to its own table (the names, ranges, units and meanings are written
// there, the defaults may differ per estimator) and builds the settings with temporal_settings().
// Deterministic: the same inputs give the same bits whatever the thread count (every pixel is
// computed on its own from the previous frame's buffers, in double).
#pragma once

#include <vector>

#include "estimators/estimator.h"
#include "scenes/gbuffer.h"

namespace aoeval {

enum class HistoryRead { bilinear, catmull_rom };

struct TemporalSettings {
  HistoryRead history_read = HistoryRead::bilinear;  // how the value's history is resampled
  int history_limit = 0;         // the longest history a pixel keeps, frames (>= 1)
  double alpha_min = 0.0;        // the smallest blend factor of the current frame, [0, 1]
  bool clamp = false;            // clamp the reprojected history to the neighbourhood's range
  double gamma = 0.0;            // half-width of that range, in standard deviations
  double clamp_sigma_min = 0.0;  // the smallest half-width, AO units
  int clamp_radius = 0;          // the window is (2 clamp_radius + 1)^2 pixels
  double antilag = 0.0;          // anti-lag threshold, standard errors of the window mean (0: off)
  double antilag_min = 0.0;      // the smallest anti-lag threshold, AO units
  int antilag_radius = 0;        // the anti-lag window is (2 antilag_radius + 1)^2 pixels
  int antilag_frames = 1;        // the fast history's length, frames (1: this frame's window alone)
  int antilag_spread_frames =
      0;  // the observed spread of the test over about this many frames (0: off)
  double antilag_shift_power = 1.0;   // a tripped history keeps (tau / d)^this of the difference
  double antilag_length_power = 2.0;  // and (tau / d)^this of its length
};

// The defaults an estimator gives the fragment's parameters. The reference design's own are
// TemporalDefaults{}: a 3x3 TAA clamp with gamma 1 (Salvi 2016), the D3D12 sample's minimum
// smoothing factor 0.03, and a 32-frame cap (so alpha >= max(0.03, 1/33)).
struct TemporalDefaults {
  HistoryRead history_read = HistoryRead::catmull_rom;
  int history_limit = 32;
  double alpha_min = 0.03;
  bool clamp = true;
  double gamma = 1.0;
  double clamp_sigma_min = 0.0;
  int clamp_radius = 1;
  double antilag = 0.0;
  double antilag_min = 0.02;
  int antilag_radius = 2;
  int antilag_frames = 1;
  int antilag_spread_frames = 0;
  double antilag_shift_power = 1.0;
  double antilag_length_power = 2.0;
};

// The stage's parameters, in this order: history_read, history_limit, alpha_min, clamp, gamma,
// clamp_sigma_min, clamp_radius, antilag, antilag_min, antilag_radius, antilag_frames,
// antilag_spread_frames, antilag_shift_power, antilag_length_power (names, ranges, units and
// meanings written here once).
std::vector<ParamSpec> temporal_params(const TemporalDefaults& defaults = {});
// Reads the fragment's parameters from an estimator's resolved set.
TemporalSettings temporal_settings(const ParamSet& params);

// Runs the stage frame after frame. Not thread-safe (one instance per estimator instance).
class TemporalAccumulator {
 public:
  explicit TemporalAccumulator(const TemporalSettings& settings);

  // Forgets the history: the next accumulate() starts afresh everywhere (a still frame, frame 0).
  void reset();
  bool has_history() const { return pending_ || !history_.empty(); }

  // Accumulates one frame: `current` holds this frame's raw value per pixel (g.pixel_count()
  // values, read where g is covered). The G-buffer's motion and disoccluded are read when present
  // (a still G-buffer has neither: zero motion, nothing disoccluded). A size change resets.
  void accumulate(const GBuffer& g, const std::vector<float>& current);

  // This frame's results, per pixel (0 where not covered).
  const std::vector<float>& value() const { return value_; }            // the accumulated value
  const std::vector<float>& moment1() const { return moment1_; }        // E[x]
  const std::vector<float>& moment2() const { return moment2_; }        // E[x^2]
  const std::vector<float>& history_length() const { return length_; }  // frames, incl. this one
  // Where this frame started afresh (disoccluded, no valid tap, first frame): 1, else 0.
  const std::vector<uint8_t>& was_reset() const { return reset_; }

  // What the next frame reprojects as the value's history: value() unless replaced. SVGF feeds its
  // first a-trous iteration back (Schied et al. 2017 §4.1, "we use the result of the first wavelet
  // iteration as the color history"); the moments' history stays the raw moments.
  void replace_history(const std::vector<float>& history);

 private:
  TemporalSettings settings_;
  int width_ = 0, height_ = 0;
  std::vector<float> value_, moment1_, moment2_, length_;
  std::vector<uint8_t> reset_;
  // Frame k - 1, read by frame k. A frame's results become these at the start of the next
  // accumulate() (buffers swapped, not copied): `pending_` until then, and `replaced_` where
  // replace_history() has already set history_.
  std::vector<float> history_, prev_moment1_, prev_moment2_, prev_length_, prev_object_;
  std::vector<uint8_t> prev_covered_;
  bool pending_ = false, replaced_ = false;
  // Buffers reused from frame to frame: the coverage and the clamp ranges.
  std::vector<uint8_t> covered_;
  std::vector<double> clamp_lo_, clamp_hi_;
  std::vector<float> prev_box_;  // the window means of frame k - 1's raw first moment (anti-lag)
  // Anti-lag's fast history of the window mean, its variance and its length (frame k - 1).
  std::vector<float> prev_fast_, prev_fast_var_, prev_fast_length_;
  // The spread of the first moment, Var m1 / Var x (anti-lag): this frame's and frame k - 1's.
  std::vector<float> spread_, prev_spread_;
  // The observed spread of the anti-lag's difference, E[(f - hbar)^2], and its length (frame k -
  // 1).
  std::vector<float> prev_observed_, prev_observed_length_, prev_difference_;
};

}  // namespace aoeval
