#include "estimators/temporal/temporal_stage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimators/pixel_loops.h"
#include "scenes/bilinear_taps.h"

namespace aoeval {

std::vector<ParamSpec> temporal_params(const TemporalDefaults& d) {
  return {
      choice_param(
          {.name = "history_read",
           .def = d.history_read == HistoryRead::catmull_rom ? "catmull-rom" : "bilinear",
           .choices = {"catmull-rom", "bilinear"},
           .meaning = "temporal stage: how the history is resampled at the reprojected position: "
                      "the 4x4 Catmull-Rom spline (Keys 1981; TAA's bicubic history read, Karis "
                      "2014), bilinear where a tap is invalid, or bilinear everywhere (blurs under "
                      "motion)"}),
      int_param({.name = "history_limit",
                 .def = d.history_limit,
                 .min = 1,
                 .max = 4096,
                 .spacing = Spacing::log,
                 .unit = "frames",
                 .meaning =
                     "temporal stage: the longest history a pixel keeps; the blend factor is never "
                     "below 1/(history_limit+1) (Schied et al. 2017 §4.1, history length)"}),
      real_param({.name = "alpha_min",
                  .def = d.alpha_min,
                  .min = 0.0,
                  .max = 1.0,
                  .spacing = Spacing::linear,
                  .unit = "",
                  .meaning = "temporal stage: the smallest weight of the current frame, alpha = "
                             "max(alpha_min, 1/(L+1)) (Schied et al. 2017 §4.1; 1 = no history)"}),
      bool_param({.name = "clamp",
                  .def = d.clamp,
                  .meaning =
                      "temporal stage: clamp the reprojected history to the current frame's "
                      "neighbourhood, mean +- max(gamma sigma, clamp_sigma_min) (Salvi 2016)"}),
      real_param(
          {.name = "gamma",
           .def = d.gamma,
           .min = 0.0,
           .max = 100.0,
           .spacing = Spacing::linear,
           .unit = "standard deviations",
           .meaning =
               "temporal stage: half-width of the clamp range around the neighbourhood's mean "
               "(Salvi 2016; the D3D12 denoised AO sample's std.dev gamma)"}),
      real_param({.name = "clamp_sigma_min",
                  .def = d.clamp_sigma_min,
                  .min = 0.0,
                  .max = 1.0,
                  .spacing = Spacing::linear,
                  .unit = "AO",
                  .meaning =
                      "temporal stage: the smallest half-width of the clamp range, so that a flat "
                      "noisy neighbourhood does not clamp at random (the D3D12 sample's minimum "
                      "std.dev)"}),
      int_param(
          {.name = "clamp_radius",
           .def = d.clamp_radius,
           .min = 0,
           .max = 16,
           .spacing = Spacing::linear,
           .unit = "pixels",
           .meaning =
               "temporal stage: the clamp's neighbourhood is (2 clamp_radius + 1)^2 pixels of "
               "the current frame (1 = the 3x3 of TAA)"}),
      real_param(
          {.name = "antilag",
           .def = d.antilag,
           .min = 0.0,
           .max = 100.0,
           .spacing = Spacing::linear,
           .unit = "standard errors",
           .meaning =
               "temporal stage: anti-lag threshold: where this frame's window mean differs "
               "from the history's by more than antilag sigma/sqrt(n) + antilag_min, the "
               "history is shortened by (threshold/difference)^antilag_length_power and moved "
               "towards this frame (antilag_shift_power) (A-SVGF's temporal gradient, Schied et "
               "al. 2018; NRD REBLUR anti-lag); 0 = off"}),
      real_param({.name = "antilag_min",
                  .def = d.antilag_min,
                  .min = 0.0,
                  .max = 1.0,
                  .spacing = Spacing::linear,
                  .unit = "AO",
                  .meaning =
                      "temporal stage: the smallest anti-lag threshold, so that a flat, noiseless "
                      "window does not shorten the history for a rounding"}),
      int_param(
          {.name = "antilag_radius",
           .def = d.antilag_radius,
           .min = 0,
           .max = 16,
           .spacing = Spacing::linear,
           .unit = "pixels",
           .meaning =
               "temporal stage: the anti-lag window is (2 antilag_radius + 1)^2 pixels (its mean "
               "low-passes the noise the comparison must ignore)"}),
      int_param(
          {.name = "antilag_frames",
           .def = d.antilag_frames,
           .min = 1,
           .max = 64,
           .spacing = Spacing::log,
           .unit = "frames",
           .meaning =
               "temporal stage: anti-lag compares the slow history with a fast history of the "
               "window mean at most this long (NRD REBLUR's fast history), whose noise is "
               "sqrt(antilag_frames) times smaller than one frame's; 1 = this frame's window"}),
      int_param(
          {.name = "antilag_spread_frames",
           .def = d.antilag_spread_frames,
           .min = 0,
           .max = 64,
           .spacing = Spacing::linear,
           .unit = "frames",
           .meaning =
               "temporal stage: anti-lag's noise is at least the spread its own difference has "
               "shown from frame to frame over about this many frames (per pixel, reprojected; "
               "A-SVGF normalises its temporal gradient by the signal's own spread), for inputs "
               "whose pixels are not independent (a spatial denoise, a noise pattern that turns "
               "every frame); 0 = the independent-pixel noise alone"}),
      real_param(
          {.name = "antilag_shift_power",
           .def = d.antilag_shift_power,
           .min = 1.0,
           .max = 16.0,
           .spacing = Spacing::linear,
           .unit = "",
           .meaning =
               "temporal stage: where the anti-lag trips (difference d above its threshold tau), "
               "the history moves by d (1 - (tau/d)^antilag_shift_power): 1 = soft thresholding "
               "(the history keeps tau of the change), 2 = the non-negative garrote (Breiman "
               "1995), higher = a difference well above tau is taken nearly whole while one just "
               "above it (noise) moves the history little"}),
      real_param(
          {.name = "antilag_length_power",
           .def = d.antilag_length_power,
           .min = 0.0,
           .max = 8.0,
           .spacing = Spacing::linear,
           .unit = "",
           .meaning =
               "temporal stage: where the anti-lag trips, the history length read is scaled by "
               "(tau/d)^antilag_length_power (0 = kept: the shift alone; a larger power fades "
               "the rest faster at the price of more noise)"}),
  };
}

TemporalSettings temporal_settings(const ParamSet& p) {
  TemporalSettings s;
  s.history_read =
      p.choice("history_read") == "catmull-rom" ? HistoryRead::catmull_rom : HistoryRead::bilinear;
  s.history_limit = static_cast<int>(p.integer("history_limit"));
  s.alpha_min = p.real("alpha_min");
  s.clamp = p.boolean("clamp");
  s.gamma = p.real("gamma");
  s.clamp_sigma_min = p.real("clamp_sigma_min");
  s.clamp_radius = static_cast<int>(p.integer("clamp_radius"));
  s.antilag = p.real("antilag");
  s.antilag_min = p.real("antilag_min");
  s.antilag_radius = static_cast<int>(p.integer("antilag_radius"));
  s.antilag_frames = static_cast<int>(p.integer("antilag_frames"));
  s.antilag_spread_frames = static_cast<int>(p.integer("antilag_spread_frames"));
  s.antilag_shift_power = p.real("antilag_shift_power");
  s.antilag_length_power = p.real("antilag_length_power");
  return s;
}

TemporalAccumulator::TemporalAccumulator(const TemporalSettings& settings) : settings_(settings) {}

void TemporalAccumulator::reset() {
  pending_ = replaced_ = false;
  history_.clear();
  prev_moment1_.clear();
  prev_moment2_.clear();
  prev_length_.clear();
  prev_object_.clear();
  prev_covered_.clear();
  prev_box_.clear();
  prev_fast_.clear();
  prev_fast_var_.clear();
  prev_fast_length_.clear();
  prev_spread_.clear();
  prev_observed_.clear();
  prev_observed_length_.clear();
  prev_difference_.clear();
}

void TemporalAccumulator::replace_history(const std::vector<float>& history) {
  if (!pending_ || history.size() != value_.size()) return;
  history_ = history;
  replaced_ = true;
}

namespace {

// Window statistics over the covered pixels of every (2 r + 1)^2 window, population, in double.
// Running sums: down a chunk of kChunkRows rows, each column's sums over the window's rows gain
// the row that enters and lose the row that leaves; along a row, the window's sums gain the
// column that enters and lose the one that leaves (a few additions a pixel, not 2 (2 r + 1)).
// Every chunk starts afresh at fixed rows, so the order of the sums is the same whatever the
// threads. `use(p, n, mean, var)` is called for every covered pixel p (n >= 1: p is covered).
constexpr int kChunkRows = 16;
template <class Use>
void window_stats(const std::vector<float>& x, const std::vector<uint8_t>& covered, int w, int h,
                  int r, const Use& use) {
  const int chunks = (h + kChunkRows - 1) / kChunkRows;
  tbb::parallel_for(tbb::blocked_range<int>(0, chunks), [&](const tbb::blocked_range<int>& range) {
    std::vector<double> cn(w), c1(w), c2(w);
    double* __restrict sn = cn.data(), * __restrict s1 = c1.data(), * __restrict s2 = c2.data();
    // Adds row b to the column sums (sign +1) or takes it away (-1): a vectorised loop.
    const auto add_row = [&](int b, double sign) {
      const uint8_t* __restrict cov = covered.data() + static_cast<size_t>(b) * w;
      const float* __restrict xb = x.data() + static_cast<size_t>(b) * w;
      for (int a = 0; a < w; ++a) {
        const double v = cov[a] ? xb[a] : 0.0;
        sn[a] += cov[a] ? sign : 0.0;
        s1[a] += sign * v;
        s2[a] += sign * (v * v);
      }
    };
    for (int chunk = range.begin(); chunk < range.end(); ++chunk) {
      const int j0 = chunk * kChunkRows, j1 = std::min(h, j0 + kChunkRows);
      std::fill(cn.begin(), cn.end(), 0.0);
      std::fill(c1.begin(), c1.end(), 0.0);
      std::fill(c2.begin(), c2.end(), 0.0);
      for (int b = std::max(0, j0 - r); b <= std::min(h - 1, j0 + r); ++b) add_row(b, 1.0);
      for (int j = j0; j < j1; ++j) {
        if (j > j0) {
          if (j + r < h) add_row(j + r, 1.0);
          if (j - r - 1 >= 0) add_row(j - r - 1, -1.0);
        }
        double n = 0.0, sum = 0.0, sum2 = 0.0;
        for (int a = 0; a <= std::min(w - 1, r - 1); ++a) n += cn[a], sum += c1[a], sum2 += c2[a];
        const uint8_t* cov = covered.data() + static_cast<size_t>(j) * w;
        for (int i = 0; i < w; ++i) {
          if (i + r < w) n += cn[i + r], sum += c1[i + r], sum2 += c2[i + r];
          if (i - r - 1 >= 0) n -= cn[i - r - 1], sum -= c1[i - r - 1], sum2 -= c2[i - r - 1];
          if (!cov[i]) continue;
          const double mean = sum / n;
          use(static_cast<size_t>(j) * w + i, n, mean, std::max(0.0, sum2 / n - mean * mean));
        }
      }
    }
  });
}

// The clamp range of a covered pixel p: mean +- max(gamma sigma, sigma_min) of the current frame's
// raw values over the covered pixels of its (2 clamp_radius + 1)^2 window.
void clamp_range(const TemporalSettings& s, size_t p, double mean, double var,
                 std::vector<double>& lo, std::vector<double>& hi) {
  const double half = std::max(s.gamma * std::sqrt(var), s.clamp_sigma_min);
  lo[p] = mean - half;
  hi[p] = mean + half;
}

// The anti-lag's window means and variances (float), with n[p] the covered count (0: none).
struct BoxStats {
  std::vector<float> mean, var, n;
  void resize(size_t size) {  // every element is 0 until a covered pixel's statistics are set
    mean.assign(size, 0.0f);
    var.assign(size, 0.0f);
    n.assign(size, 0.0f);
  }
  void set(size_t p, double count, double m, double v) {
    mean[p] = static_cast<float>(m);
    var[p] = static_cast<float>(v);
    n[p] = static_cast<float>(count);
  }
};

// The Catmull-Rom weights of the four taps at offsets -1, 0, 1, 2 from the texel at or left of a
// position t in [0, 1) past it (Keys 1981 with a = -1/2): they sum to 1, and t = 0 gives (0, 1, 0,
// 0), so an integer offset reads the texel exactly.
void catmull_rom_weights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

// The Catmull-Rom read of `image` at the continuous position (x, y) (pixel centres at i + 0.5), or
// false when a tap with a non-zero weight is off screen or not valid (the caller reads bilinearly
// then). The result is kept within the range of the 2x2 texels around the position.
template <class Valid>
bool catmull_rom_read(const std::vector<float>& image, double x, double y, int w, int h,
                      const Valid& valid, double* out) {
  const double fx = x - 0.5, fy = y - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  double wx[4], wy[4];
  catmull_rom_weights(fx - x0, wx);
  catmull_rom_weights(fy - y0, wy);
  const int a0 = static_cast<int>(x0) - 1, b0 = static_cast<int>(y0) - 1;
  double sum = 0.0, lo = 1e300, hi = -1e300;
  for (int dy = 0; dy < 4; ++dy) {
    if (wy[dy] == 0.0) continue;
    const int b = b0 + dy;
    for (int dx = 0; dx < 4; ++dx) {
      if (wx[dx] == 0.0) continue;
      const int a = a0 + dx;
      if (a < 0 || b < 0 || a >= w || b >= h) return false;
      const int t = b * w + a;
      if (!valid(t)) return false;
      const double v = image[t];
      sum += wx[dx] * wy[dy] * v;
      if ((dx == 1 || dx == 2) && (dy == 1 || dy == 2)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  *out = std::clamp(sum, lo, hi);
  return true;
}

}  // namespace

void TemporalAccumulator::accumulate(const GBuffer& g, const std::vector<float>& current) {
  const size_t n = g.pixel_count();
  if (current.size() != n)
    throw std::invalid_argument("temporal stage: " + std::to_string(current.size()) +
                                " values for " + std::to_string(n) + " pixels");
  if (g.width != width_ || g.height != height_) reset();
  width_ = g.width;
  height_ = g.height;
  if (pending_) {  // the last frame's results become frame k - 1's buffers
    if (!replaced_) history_.swap(value_);
    prev_moment1_.swap(moment1_);
    prev_moment2_.swap(moment2_);
    prev_length_.swap(length_);
    pending_ = replaced_ = false;
  }
  const bool history = has_history();
  const bool moving = !g.motion.empty(), disocclusion = !g.disoccluded.empty();
  // Every pixel is written below (0 where not covered): no clearing.
  for (std::vector<float>* v : {&value_, &moment1_, &moment2_, &length_}) v->resize(n);
  reset_.resize(n);
  const TemporalSettings& s = settings_;
  std::vector<uint8_t>& covered = covered_;
  covered.resize(n);
  for (size_t p = 0; p < n; ++p) covered[p] = g.covered(p);
  // The current frame's window statistics: the clamp's ranges and the anti-lag's window means,
  // from one pass where both take the same window (rtao's defaults).
  const bool clamp = s.clamp && history;
  BoxStats box;
  if (clamp) {
    clamp_lo_.resize(n);
    clamp_hi_.resize(n);
  }
  if (s.antilag > 0.0) {
    box.resize(n);
    spread_.resize(n);  // every pixel is written below
  }
  if (clamp && s.antilag > 0.0 && s.clamp_radius == s.antilag_radius) {
    window_stats(current, covered, g.width, g.height, s.clamp_radius,
                 [&](size_t p, double count, double mean, double var) {
                   clamp_range(s, p, mean, var, clamp_lo_, clamp_hi_);
                   box.set(p, count, mean, var);
                 });
  } else {
    if (clamp)
      window_stats(current, covered, g.width, g.height, s.clamp_radius,
                   [&](size_t p, double, double mean, double var) {
                     clamp_range(s, p, mean, var, clamp_lo_, clamp_hi_);
                   });
    if (s.antilag > 0.0)
      window_stats(
          current, covered, g.width, g.height, s.antilag_radius,
          [&](size_t p, double count, double mean, double var) { box.set(p, count, mean, var); });
  }
  const bool antilag = s.antilag > 0.0 && prev_box_.size() == n;
  // The fast history is kept only when it is longer than one frame (antilag_frames = 1: f is this
  // frame's window mean, its variance the window's sigma^2 / n).
  const bool fast_history = s.antilag > 0.0 && s.antilag_frames > 1;
  std::vector<float> fast, fast_var, fast_length;
  if (fast_history) {
    fast.assign(n, 0.0f);
    fast_var.assign(n, 0.0f);
    fast_length.assign(n, 0.0f);
  }
  // The observed spread of the difference (antilag_spread_frames > 0).
  const bool observe = s.antilag > 0.0 && s.antilag_spread_frames > 0;
  std::vector<float> observed, observed_length, difference;
  if (observe) {
    observed.assign(n, 0.0f);
    observed_length.assign(n, 0.0f);
    difference.assign(n, 0.0f);
  }
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!covered[p]) {
      value_[p] = moment1_[p] = moment2_[p] = length_[p] = 0.0f;
      if (s.antilag > 0.0) spread_[p] = 0.0f;
      reset_[p] = 0;
      return;
    }
    reset_[p] = 0;
    const double x = current[p];
    auto start_afresh = [&] {
      value_[p] = static_cast<float>(x);
      moment1_[p] = static_cast<float>(x);
      moment2_[p] = static_cast<float>(x * x);
      length_[p] = 1.0f;
      reset_[p] = 1;
      if (s.antilag > 0.0) spread_[p] = 1.0f;  // the first moment is one frame's value
      if (fast_history) {  // the fast history starts with this frame's window mean
        fast[p] = box.mean[p];
        fast_var[p] = box.var[p] / box.n[p];
        fast_length[p] = 1.0f;
      }
      if (observe) {  // one sample of what independent pixels would give, until frames are seen
        observed[p] = 2.0f * box.var[p] / box.n[p];
        observed_length[p] = 1.0f;
      }
    };
    if (!history || (disocclusion && g.disoccluded[p] > 0.5f)) return start_afresh();
    // Reverse reprojection (step 1) and the bilinear read over valid texels (step 2).
    const double mx = moving ? g.motion[p].x : 0.0, my = moving ? g.motion[p].y : 0.0;
    const float object = g.object_id[p];
    const auto valid = [&](int t) { return prev_covered_[t] != 0 && prev_object_[t] == object; };
    const double qx = i + 0.5 - mx, qy = j + 0.5 - my;
    // No motion (a static camera, the pixels that hold still): the one tap p of weight 1, what
    // bilinear_taps gives at a whole-pixel position, without its four candidates.
    BilinearTaps taps;
    if (mx == 0.0 && my == 0.0) {
      if (valid(static_cast<int>(p))) {
        taps.index[0] = static_cast<int>(p);
        taps.weight[0] = taps.total = 1.0;
        taps.taps = 1;
      }
    } else {
      taps = bilinear_taps(qx, qy, g.width, g.height, valid);
    }
    if (taps.taps == 0) return start_afresh();
    // The bilinear read of one of frame k - 1's buffers over the valid taps (weights renormalised
    // once, for every buffer read).
    double weight[4];
    for (int t = 0; t < taps.taps; ++t) weight[t] = taps.weight[t] / taps.total;
    const auto read = [&](const std::vector<float>& image) {
      double sum = 0.0;
      for (int t = 0; t < taps.taps; ++t) sum += weight[t] * image[taps.index[t]];
      return sum;
    };
    double h = read(history_), len = read(prev_length_);
    const double m1 = read(prev_moment1_), m2 = read(prev_moment2_);
    // At a whole-pixel offset both reads are the one texel's value (the Catmull-Rom weights are
    // (0, 1, 0, 0) on each axis): the bilinear read stands, the same bits.
    const bool whole = qx - 0.5 == std::floor(qx - 0.5) && qy - 0.5 == std::floor(qy - 0.5);
    double sharp = 0.0;
    if (s.history_read == HistoryRead::catmull_rom && !whole &&
        catmull_rom_read(history_, qx, qy, g.width, g.height, valid, &sharp))
      h = sharp;
    // Anti-lag (step 5b): the fast history of the window mean against the raw history's at q.
    if (antilag) {
      const double hbar = read(prev_box_);
      const double one_frame = box.var[p] / box.n[p];  // the variance of one frame's window mean
      double f = box.mean[p], fvar = one_frame;
      if (fast_history) {
        const double flen = read(prev_fast_length_);
        const double a = std::max(1.0 / (flen + 1.0), 1.0 / s.antilag_frames);
        f = a * box.mean[p] + (1.0 - a) * read(prev_fast_);
        fvar = a * a * one_frame + (1.0 - a) * (1.0 - a) * read(prev_fast_var_);
        fast[p] = static_cast<float>(f);
        fast_var[p] = static_cast<float>(fvar);
        fast_length[p] = static_cast<float>(std::min(flen + 1.0, double(s.antilag_frames)));
      }
      // The difference of two noisy means: hbar is the window mean of the first moments, whose
      // variance is one frame's times their spread read at q (1 / L for a running mean of L
      // frames, alpha / (2 - alpha) at a fixed blend factor).
      const double d = std::abs(f - hbar);
      double noise = fvar + one_frame * read(prev_spread_);
      bool test = true;
      if (observe) {
        // The observed spread (step 5c): the noise is at least the variance this pixel's
        // difference D = f - hbar has shown over about antilag_spread_frames frames (a running
        // mean at first), each frame's term the halved square of D's change since the frame
        // before (Rice 1984; a change of the truth that persists cancels in it), D^2 itself at
        // the first frame after a reset. Once the mean is full, the term is capped at 9 times
        // the noise (3 standard errors: 99.7 % of a normal difference's mass; a real change
        // raises the estimate by at most (1 - b) + 9 b a frame).
        const double seen = read(prev_observed_), seen_length = read(prev_observed_length_);
        noise = std::max(noise, seen);
        const double b = std::max(1.0 / (seen_length + 1.0), 1.0 / s.antilag_spread_frames);
        const double signed_d = f - hbar;
        difference[p] = static_cast<float>(signed_d);
        const double change = signed_d - read(prev_difference_);
        double d2 = seen_length > 1.5 ? 0.5 * change * change : d * d;
        if (seen_length >= s.antilag_spread_frames - 0.5) d2 = std::min(d2, 9.0 * noise);
        observed[p] = static_cast<float>((1.0 - b) * seen + b * d2);
        observed_length[p] =
            static_cast<float>(std::min(seen_length + 1.0, double(s.antilag_spread_frames)));
        test = seen_length >= s.antilag_spread_frames - 0.5;  // the spread is full (step 5c)
      }
      const double tau = s.antilag * std::sqrt(noise) + s.antilag_min;
      if (test && d > tau) {
        // The powers 1 (shift) and 2 (length) are computed as products: the bits of the stage
        // before the powers were parameters.
        const double r = tau / d;
        len *= s.antilag_length_power == 2.0 ? r * r : std::pow(r, s.antilag_length_power);
        const double keep = s.antilag_shift_power == 1.0 ? r : std::pow(r, s.antilag_shift_power);
        // The shift moves the history by the window mean's change, which a pixel at an edge of
        // that window need not share: a history at 1 beside neighbours that brightened would
        // leave [0, 1]. The stage's values are AO (every estimator through it writes [0, 1]), so
        // the shifted history is kept there; it only moves closer to any truth.
        h = std::clamp(h + (f - hbar) * (1.0 - keep), 0.0, 1.0);
      }
    }
    // Neighbourhood clamp of the history (step 5).
    if (s.clamp) h = std::clamp(h, clamp_lo_[p], clamp_hi_[p]);
    // The exponential history with its minimum blend factor (step 4).
    const double alpha = std::max(s.alpha_min, 1.0 / (len + 1.0));
    value_[p] = static_cast<float>(alpha * x + (1.0 - alpha) * h);
    if (s.antilag > 0.0)  // the first moment's spread, Var m1 / Var x (independent frames)
      spread_[p] = static_cast<float>(alpha * alpha + (1.0 - alpha) * (1.0 - alpha) *
                                                          (antilag ? read(prev_spread_) : 1.0));
    moment1_[p] = static_cast<float>(alpha * x + (1.0 - alpha) * m1);
    moment2_[p] = static_cast<float>(alpha * x * x + (1.0 - alpha) * m2);
    length_[p] = static_cast<float>(std::min(len + 1.0, static_cast<double>(s.history_limit)));
  });
  pending_ = true;  // value_, moment1_, moment2_ and length_ become frame k - 1's at the next frame
  prev_object_ = g.object_id;
  prev_covered_.swap(covered_);
  if (s.antilag > 0.0) {  // read at covered texels only: the others are left as they were
    prev_box_.resize(n);
    window_stats(
        moment1_, prev_covered_, g.width, g.height, s.antilag_radius,
        [&](size_t p, double, double mean, double) { prev_box_[p] = static_cast<float>(mean); });
  } else {
    prev_box_.clear();
  }
  prev_fast_ = std::move(fast);
  prev_fast_var_ = std::move(fast_var);
  prev_fast_length_ = std::move(fast_length);
  prev_spread_.swap(spread_);
  prev_observed_ = std::move(observed);
  prev_observed_length_ = std::move(observed_length);
  prev_difference_ = std::move(difference);
}

}  // namespace aoeval
