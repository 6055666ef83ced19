#include "estimators/temporal/temporal_stage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimators/pixel_loops.h"
#include "scenes/bilinear_taps.h"

namespace aoeval {

std::vector<ParamSpec> temporal_params(const TemporalDefaults& d) {
  return {
      int_param("history_limit", d.history_limit, 1, 4096, Spacing::log, "frames",
                "temporal stage: the longest history a pixel keeps; the blend factor is never "
                "below 1/(history_limit+1) (Schied et al. 2017 §4.1, history length)"),
      real_param("alpha_min", d.alpha_min, 0.0, 1.0, Spacing::linear, "",
                 "temporal stage: the smallest weight of the current frame, alpha = "
                 "max(alpha_min, 1/(L+1)) (Schied et al. 2017 §4.1; 1 = no history)"),
      bool_param("clamp", d.clamp,
                 "temporal stage: clamp the reprojected history to the current frame's "
                 "neighbourhood, mean +- max(gamma sigma, clamp_sigma_min) (Salvi 2016)"),
      real_param("gamma", d.gamma, 0.0, 100.0, Spacing::linear, "standard deviations",
                 "temporal stage: half-width of the clamp range around the neighbourhood's mean "
                 "(Salvi 2016; the D3D12 denoised AO sample's std.dev gamma)"),
      real_param(
          "clamp_sigma_min", d.clamp_sigma_min, 0.0, 1.0, Spacing::linear, "AO",
          "temporal stage: the smallest half-width of the clamp range, so that a flat "
          "noisy neighbourhood does not clamp at random (the D3D12 sample's minimum std.dev)"),
      int_param("clamp_radius", d.clamp_radius, 0, 16, Spacing::linear, "pixels",
                "temporal stage: the clamp's neighbourhood is (2 clamp_radius + 1)^2 pixels of "
                "the current frame (1 = the 3x3 of TAA)"),
  };
}

TemporalSettings temporal_settings(const ParamSet& p) {
  TemporalSettings s;
  s.history_limit = static_cast<int>(p.integer("history_limit"));
  s.alpha_min = p.real("alpha_min");
  s.clamp = p.boolean("clamp");
  s.gamma = p.real("gamma");
  s.clamp_sigma_min = p.real("clamp_sigma_min");
  s.clamp_radius = static_cast<int>(p.integer("clamp_radius"));
  return s;
}

TemporalAccumulator::TemporalAccumulator(const TemporalSettings& settings) : settings_(settings) {}

void TemporalAccumulator::reset() {
  history_.clear();
  prev_moment1_.clear();
  prev_moment2_.clear();
  prev_length_.clear();
  prev_object_.clear();
  prev_covered_.clear();
}

void TemporalAccumulator::replace_history(const std::vector<float>& history) {
  if (history.size() == history_.size()) history_ = history;
}

namespace {

// The clamp range of pixel (i, j): mean +- max(gamma sigma, sigma_min) of the current frame's raw
// values over the covered pixels of the window (population statistics, in double).
struct Range {
  double lo, hi;
};
Range clamp_range(const GBuffer& g, const std::vector<float>& x, int i, int j,
                  const TemporalSettings& s) {
  double n = 0.0, sum = 0.0, sum2 = 0.0;
  const int r = s.clamp_radius;
  for (int b = std::max(0, j - r); b <= std::min(g.height - 1, j + r); ++b)
    for (int a = std::max(0, i - r); a <= std::min(g.width - 1, i + r); ++a) {
      const size_t q = g.index(a, b);
      if (!g.covered(q)) continue;
      n += 1.0;
      sum += x[q];
      sum2 += static_cast<double>(x[q]) * x[q];
    }
  const double mean = sum / n;  // n >= 1: the pixel itself is covered
  const double sigma = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  const double half = std::max(s.gamma * sigma, s.clamp_sigma_min);
  return {mean - half, mean + half};
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
  const bool history = has_history();
  const bool moving = !g.motion.empty(), disocclusion = !g.disoccluded.empty();
  value_.assign(n, 0.0f);
  moment1_.assign(n, 0.0f);
  moment2_.assign(n, 0.0f);
  length_.assign(n, 0.0f);
  reset_.assign(n, 0);
  const TemporalSettings& s = settings_;
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!g.covered(p)) return;
    const double x = current[p];
    auto start_afresh = [&] {
      value_[p] = static_cast<float>(x);
      moment1_[p] = static_cast<float>(x);
      moment2_[p] = static_cast<float>(x * x);
      length_[p] = 1.0f;
      reset_[p] = 1;
    };
    if (!history || (disocclusion && g.disoccluded[p] > 0.5f)) return start_afresh();
    // Reverse reprojection (step 1) and the bilinear read over valid texels (step 2).
    const double mx = moving ? g.motion[p].x : 0.0, my = moving ? g.motion[p].y : 0.0;
    const float object = g.object_id[p];
    const BilinearTaps taps =
        bilinear_taps(i + 0.5 - mx, j + 0.5 - my, g.width, g.height,
                      [&](int t) { return prev_covered_[t] != 0 && prev_object_[t] == object; });
    if (taps.taps == 0) return start_afresh();
    double h = 0.0, m1 = 0.0, m2 = 0.0, len = 0.0;
    for (int t = 0; t < taps.taps; ++t) {
      const double w = taps.weight[t] / taps.total;
      const int q = taps.index[t];
      h += w * history_[q];
      m1 += w * prev_moment1_[q];
      m2 += w * prev_moment2_[q];
      len += w * prev_length_[q];
    }
    // Neighbourhood clamp of the history (step 5).
    if (s.clamp) {
      const Range range = clamp_range(g, current, i, j, s);
      h = std::clamp(h, range.lo, range.hi);
    }
    // The exponential history with its minimum blend factor (step 4).
    const double alpha = std::max(s.alpha_min, 1.0 / (len + 1.0));
    value_[p] = static_cast<float>(alpha * x + (1.0 - alpha) * h);
    moment1_[p] = static_cast<float>(alpha * x + (1.0 - alpha) * m1);
    moment2_[p] = static_cast<float>(alpha * x * x + (1.0 - alpha) * m2);
    length_[p] = static_cast<float>(std::min(len + 1.0, static_cast<double>(s.history_limit)));
  });
  history_ = value_;
  prev_moment1_ = moment1_;
  prev_moment2_ = moment2_;
  prev_length_ = length_;
  prev_object_ = g.object_id;
  prev_covered_.assign(n, 0);
  for (size_t p = 0; p < n; ++p) prev_covered_[p] = g.covered(p);
}

}  // namespace aoeval
