#include "estimators/rtao/svgf.h"

#include <algorithm>
#include <cmath>

#include "estimators/pixel_loops.h"

namespace aoeval {

namespace {

// The B3-spline's 1D taps (Dammertz et al. 2010; Schied et al. 2017 §4.3): h = outer product.
constexpr float kB3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};

// The depth and normal terms of w_z w_n (eqs. 3, 4) as one exponent, so that one exp serves the
// whole weight: w_n = exp(sigma_n log(n_p . n_q)). Returns -infinity where n_p . n_q <= 0 (w = 0).
float depth_normal_exponent(const GBuffer& g, const std::vector<float>& gradient, size_t p,
                            size_t q, int dx, int dy, const SvgfSettings& s) {
  const float cos_n = glm::dot(g.normal[p], g.normal[q]);
  if (!(cos_n > 0.0f)) return -INFINITY;
  const float zp = g.depth[p], zq = g.depth[q];
  const float along = std::abs(gradient[2 * p] * static_cast<float>(dx) +
                               gradient[2 * p + 1] * static_cast<float>(dy));
  const float eps = 1e-6f * zp;  // a numerical guard: flat, camera-facing surfaces have along = 0
  const float wz = std::abs(zp - zq) / (static_cast<float>(s.sigma_z) * along + eps);
  return static_cast<float>(s.sigma_n) * std::log(std::min(cos_n, 1.0f)) - wz;
}

}  // namespace

std::vector<float> depth_gradient(const GBuffer& g) {
  std::vector<float> out(2 * g.pixel_count(), 0.0f);
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!g.covered(p)) return;
    auto slope = [&](int a0, int b0, int a1, int b1) {
      auto in = [&](int a, int b) {
        return a >= 0 && b >= 0 && a < g.width && b < g.height && g.covered(g.index(a, b));
      };
      const bool lo = in(a0, b0), hi = in(a1, b1);
      const float z = g.depth[p];
      if (lo && hi) return 0.5f * (g.depth[g.index(a1, b1)] - g.depth[g.index(a0, b0)]);
      if (hi) return g.depth[g.index(a1, b1)] - z;
      if (lo) return z - g.depth[g.index(a0, b0)];
      return 0.0f;
    };
    out[2 * p] = slope(i - 1, j, i + 1, j);
    out[2 * p + 1] = slope(i, j - 1, i, j + 1);
  });
  return out;
}

std::vector<float> svgf_variance(const GBuffer& g, const std::vector<float>& moment1,
                                 const std::vector<float>& moment2,
                                 const std::vector<float>& history_length, const SvgfSettings& s) {
  std::vector<float> variance(g.pixel_count(), 0.0f);
  std::vector<float> gradient;
  bool spatial = false;
  for (size_t p = 0; p < g.pixel_count() && !spatial; ++p)
    spatial = g.covered(p) && history_length[p] < static_cast<float>(s.variance_frames);
  if (spatial) gradient = depth_gradient(g);
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!g.covered(p)) return;
    double m1 = moment1[p], m2 = moment2[p];
    if (history_length[p] < static_cast<float>(s.variance_frames)) {
      // §4.2: the bilateral estimate (7x7 at the paper's radius 3), depth and normal weights only.
      const int rad = s.variance_radius;
      double sw = 0.0, s1 = 0.0, s2 = 0.0;
      for (int dy = -rad; dy <= rad; ++dy)
        for (int dx = -rad; dx <= rad; ++dx) {
          const int a = i + dx, b = j + dy;
          if (a < 0 || b < 0 || a >= g.width || b >= g.height) continue;
          const size_t q = g.index(a, b);
          if (!g.covered(q)) continue;
          const float e = q == p ? 0.0f : depth_normal_exponent(g, gradient, p, q, dx, dy, s);
          const double w = std::exp(static_cast<double>(e));
          sw += w;
          s1 += w * moment1[q];
          s2 += w * moment2[q];
        }
      m1 = s1 / sw;  // sw >= 1: the centre tap
      m2 = s2 / sw;
    }
    variance[p] = static_cast<float>(std::max(0.0, m2 - m1 * m1));
  });
  return variance;
}

void atrous_iteration(const GBuffer& g, const std::vector<float>& gradient, int step,
                      const SvgfSettings& s, std::vector<float>& value,
                      std::vector<float>& variance) {
  const std::vector<float> c = value, var = variance;
  // g_3x3 of eq. 5: the variance under a 3x3 Gaussian (1/4, 1/2, 1/4)^2, over covered pixels.
  std::vector<float> blurred(g.pixel_count(), 0.0f);
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!g.covered(p)) return;
    constexpr float k[3] = {0.25f, 0.5f, 0.25f};
    float sw = 0.0f, sv = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int a = i + dx, b = j + dy;
        if (a < 0 || b < 0 || a >= g.width || b >= g.height || !g.covered(g.index(a, b))) continue;
        const float w = k[dx + 1] * k[dy + 1];
        sw += w;
        sv += w * var[g.index(a, b)];
      }
    blurred[p] = sv / sw;
  });
  for_each_pixel(g.width, g.height, [&](int i, int j) {
    const size_t p = g.index(i, j);
    if (!g.covered(p)) return;
    const float lum_denom = static_cast<float>(s.sigma_l) * std::sqrt(blurred[p]) + 1e-10f;
    float sw = 0.0f, sc = 0.0f, sv = 0.0f;
    for (int ky = -2; ky <= 2; ++ky)
      for (int kx = -2; kx <= 2; ++kx) {
        const int dx = kx * step, dy = ky * step, a = i + dx, b = j + dy;
        if (a < 0 || b < 0 || a >= g.width || b >= g.height) continue;
        const size_t q = g.index(a, b);
        if (!g.covered(q)) continue;
        const float h = kB3[kx + 2] * kB3[ky + 2];
        float w = 1.0f;  // the centre: every term is exp(0)
        if (q != p) {
          const float e = depth_normal_exponent(g, gradient, p, q, dx, dy, s) -
                          std::abs(c[p] - c[q]) / lum_denom;
          w = std::exp(e);
        }
        const float hw = h * w;
        sw += hw;
        sc += hw * c[q];
        sv += hw * hw * var[q];
      }
    value[p] = std::clamp(sc / sw, 0.0f, 1.0f);  // sw >= 9/64: the centre tap
    variance[p] = sv / (sw * sw);
  });
}

}  // namespace aoeval
