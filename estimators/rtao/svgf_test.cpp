// SVGF's spatial filter (svgf.h) against the paper's equations written pixel by pixel: the
// vectorised, tiled, parallel passes give the same bits as the plain loops with the same exp and
// log, the same bits on one thread as on many, and stay within a bound of libm's exp and log (the
// filter before it was vectorised).
#include "estimators/rtao/svgf.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "estimators/rtao/svgf_math.h"
#include "estimators/simd_isa.h"

namespace aoeval {
namespace {

int64_t ulps(float a, float b) {
  return std::abs(static_cast<int64_t>(std::bit_cast<int32_t>(a)) - std::bit_cast<int32_t>(b));
}

// Every 101st float of [-87.3, 0] and of the normal floats in (0, 1]: about 1e7 values each.
TEST(FastExp, WithinTwoUlpOfLibm) {
  int64_t worst = 0;
  for (int32_t bits = std::bit_cast<int32_t>(87.3f); bits > 0; bits -= 101) {
    const float x = -std::bit_cast<float>(bits);
    worst = std::max(worst, ulps(svgf_exp(x), std::exp(x)));
  }
  EXPECT_LE(worst, 2);
  std::printf("exp: %lld ulp at most\n", static_cast<long long>(worst));
  EXPECT_EQ(svgf_exp(0.0f), 1.0f);
  EXPECT_EQ(svgf_exp(-88.0f), 0.0f);
  EXPECT_EQ(svgf_exp(-INFINITY), 0.0f);
}

TEST(FastLog, WithinTwoUlpOfLibm) {
  int64_t worst = 0;
  for (int32_t bits = std::bit_cast<int32_t>(1.0f); bits >= 0x00800000; bits -= 101) {
    const float x = std::bit_cast<float>(bits);
    worst = std::max(worst, ulps(svgf_log(x), std::log(x)));
  }
  EXPECT_LE(worst, 2);
  std::printf("log: %lld ulp at most\n", static_cast<long long>(worst));
  EXPECT_EQ(svgf_log(1.0f), 0.0f);
}

// A 37 x 29 G-buffer with what the weights must handle: two planes meeting at a crease (a normal
// edge), a step in depth, a hole of uncovered pixels, a background column, and a bumpy normal.
GBuffer scene() {
  GBuffer g;
  g.width = 37;
  g.height = 29;
  const size_t n = g.pixel_count();
  g.coverage.assign(n, 1.0f);
  g.depth.assign(n, 0.0f);
  g.normal.assign(n, glm::vec3(0.0f));
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      if (i == 30 || (i > 10 && i < 14 && j > 5 && j < 9)) {
        g.coverage[p] = 0.0f;
        g.normal[p] = glm::vec3(0.0f, 1.0f, 0.0f);  // what the filter must not read
        continue;
      }
      const float bump = 0.2f * std::sin(0.7f * i) * std::cos(0.5f * j);
      g.normal[p] = glm::normalize(i < 18 ? glm::vec3(bump, 1.0f, 0.1f) : glm::vec3(1.0f, bump, 0));
      g.depth[p] = 2.0f + 0.05f * i + 0.02f * j + (j > 20 ? 1.5f : 0.0f);
    }
  return g;
}

struct Signal {
  std::vector<float> value, variance, moment1, moment2, length;
};
Signal signal(const GBuffer& g) {
  std::mt19937 rng(43);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Signal s;
  for (size_t p = 0; p < g.pixel_count(); ++p) {
    const bool c = g.covered(p);
    const float m1 = c ? u(rng) : 0.0f;
    s.value.push_back(c ? std::min(1.0f, m1 + 0.1f * u(rng)) : NAN);  // NaN: must not be read
    s.moment1.push_back(m1);
    s.moment2.push_back(c ? m1 * m1 + 0.05f * u(rng) : 0.0f);
    s.length.push_back(c ? static_cast<float>(1 + static_cast<int>(8 * u(rng))) : 0.0f);
  }
  return s;
}

// sigma_n = 128 (the default, 2^7: w_n by squarings) or any other value (w_n by exp and log).
SvgfSettings settings(double sigma_n = 128.0) {
  return {.sigma_z = 1.0,
          .sigma_n = sigma_n,
          .sigma_l = 4.0,
          .variance_frames = 4,
          .variance_radius = 3};
}

// Schied et al. 2017 §4.2 and eqs. 1-5 pixel by pixel (svgf.h), with the given exp and log.
template <class Exp, class Log>
float exponent(const SvgfGuide& g, size_t p, size_t q, int dx, int dy, const SvgfSettings& s,
               const Log& log) {
  const float cos_n = g.nx[p] * g.nx[q] + g.ny[p] * g.ny[q] + g.nz[p] * g.nz[q];
  if (!(cos_n > 0.0f)) return -INFINITY;
  const float along = std::abs(g.grad_x[p] * dx + g.grad_y[p] * dy);
  const float wz =
      std::abs(g.depth[p] - g.depth[q]) / (float(s.sigma_z) * along + 1e-6f * g.depth[p]);
  return float(s.sigma_n) * log(std::min(cos_n, 1.0f)) - wz;
}

template <class Exp, class Log>
std::vector<float> reference_variance(const SvgfGuide& g, const Signal& x, const SvgfSettings& s,
                                      const Exp& exp, const Log& log) {
  std::vector<float> var(x.value.size(), 0.0f);
  const int r = s.variance_radius;
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = size_t(j) * g.width + i;
      if (!g.covered[p]) continue;
      double m1 = x.moment1[p], m2 = x.moment2[p], sw = 0, s1 = 0, s2 = 0;
      if (x.length[p] >= float(s.variance_frames)) {
        var[p] = float(std::max(0.0, m2 - m1 * m1));
        continue;
      }
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int a = i + dx, b = j + dy;
          if (a < 0 || b < 0 || a >= g.width || b >= g.height) continue;
          const size_t q = size_t(b) * g.width + a;
          if (!g.covered[q]) continue;
          const double w = q == p ? 1.0 : exp(exponent<Exp>(g, p, q, dx, dy, s, log));
          sw += w;
          s1 += w * x.moment1[q];
          s2 += w * x.moment2[q];
        }
      var[p] = float(std::max(0.0, s2 / sw - (s1 / sw) * (s1 / sw)));
    }
  return var;
}

// An a-trous weight w_i = w_z w_n w_l (eqs. 3-5) of tap q = p + (dx, dy), lum being eq. 5's
// denominator at p, as the passes compute it: eqs. 3 and 5 through the reciprocals of their
// denominators, one exp, and w_n by 7 squarings where sigma_n = 128 (else by exp and log).
float fast_weight(const SvgfGuide& g, size_t p, size_t q, int dx, int dy, float lum, float cp,
                  float cq, const SvgfSettings& s) {
  const float cos_n = g.nx[p] * g.nx[q] + g.ny[p] * g.ny[q] + g.nz[p] * g.nz[q];
  const float along = std::abs(g.grad_x[p] * dx + g.grad_y[p] * dy);
  const float rz = 1.0f / (float(s.sigma_z) * along + 1e-6f * g.depth[p]), rl = 1.0f / lum;
  const float d = std::abs(g.depth[p] - g.depth[q]) * rz + std::abs(cp - cq) * rl;
  float wn = std::min(cos_n, 1.0f);
  if (s.sigma_n != 128.0) return svgf_exp(float(s.sigma_n) * svgf_log(wn) - d);
  for (int k = 0; k < 7; ++k) wn *= wn;
  return wn * svgf_exp(-d);
}
// The same as the paper writes it, with libm's exp and log (the filter before svgf_math.h).
float libm_weight(const SvgfGuide& g, size_t p, size_t q, int dx, int dy, float lum, float cp,
                  float cq, const SvgfSettings& s) {
  const float cos_n = g.nx[p] * g.nx[q] + g.ny[p] * g.ny[q] + g.nz[p] * g.nz[q];
  const float along = std::abs(g.grad_x[p] * dx + g.grad_y[p] * dy);
  const float wz =
      std::abs(g.depth[p] - g.depth[q]) / (float(s.sigma_z) * along + 1e-6f * g.depth[p]);
  return std::exp(float(s.sigma_n) * std::log(std::min(cos_n, 1.0f)) - wz -
                  std::abs(cp - cq) / lum);
}

template <class Weight>
void reference_atrous(const SvgfGuide& g, int step, const SvgfSettings& s, std::vector<float>& c,
                      std::vector<float>& var, const Weight& weight) {
  const std::vector<float> c0 = c, v0 = var;
  constexpr float b3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16},
                  k[3] = {.25f, .5f, .25f};
  auto in = [&](int a, int b) { return a >= 0 && b >= 0 && a < g.width && b < g.height; };
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = size_t(j) * g.width + i;
      if (!g.covered[p]) continue;
      float bw = 0, bv = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (in(i + dx, j + dy) && g.covered[p + dy * g.width + dx]) {
            bw += k[dx + 1] * k[dy + 1];
            bv += k[dx + 1] * k[dy + 1] * v0[p + dy * g.width + dx];
          }
      const float lum = float(s.sigma_l) * std::sqrt(bv / bw) + 1e-10f;
      float sw = 0, sc = 0, sv = 0;
      for (int ky = -2; ky <= 2; ++ky)
        for (int kx = -2; kx <= 2; ++kx) {
          const int dx = kx * step, dy = ky * step;
          if (!in(i + dx, j + dy) || !g.covered[p + dy * g.width + dx]) continue;
          const size_t q = p + dy * g.width + dx;
          const float cos_n = g.nx[p] * g.nx[q] + g.ny[p] * g.ny[q] + g.nz[p] * g.nz[q];
          if (q != p && !(cos_n > 0.0f)) continue;
          const float h = b3[kx + 2] * b3[ky + 2];
          const float w = q == p ? 1.0f : weight(g, p, q, dx, dy, lum, c0[p], c0[q], s);
          sw += h * w;
          sc += h * w * c0[q];
          sv += h * w * (h * w) * v0[q];
        }
      c[p] = std::clamp(sc / sw, 0.0f, 1.0f);
      var[p] = sv / (sw * sw);
    }
}

// The denoiser's spatial half as rtao runs it: the variance, then five a-trous passes.
template <class Variance, class Atrous>
std::vector<float> denoise(const Signal& x, const Variance& variance, const Atrous& atrous) {
  std::vector<float> c = x.value, var = variance();
  for (int i = 0; i < 5; ++i) atrous(1 << i, c, var);
  for (size_t p = 0; p < c.size(); ++p)
    if (x.length[p] == 0.0f) c[p] = 0.0f;  // uncovered: the input's NaN, left as it was
  c.insert(c.end(), var.begin(), var.end());
  return c;
}

std::vector<float> fast(const SvgfGuide& g, const Signal& x, const SvgfSettings& s = settings()) {
  return denoise(
      x, [&] { return svgf_variance(g, x.moment1, x.moment2, x.length, s); },
      [&](int step, auto& c, auto& v) { atrous_iteration(g, step, s, c, v); });
}

template <class Exp, class Log, class Weight>
std::vector<float> reference(const SvgfGuide& g, const Signal& x, const SvgfSettings& s,
                             const Exp& exp, const Log& log, const Weight& weight) {
  return denoise(
      x, [&] { return reference_variance(g, x, s, exp, log); },
      [&](int step, auto& c, auto& v) { reference_atrous(g, step, s, c, v, weight); });
}

const auto fast_exp = [](float e) { return svgf_exp(e); };
const auto fast_log = [](float x) { return svgf_log(x); };

// The guide pixel by pixel: the normal (0 where uncovered), the depth, and its central differences
// over covered pixels (one-sided where one neighbour is, 0 where none is or p is uncovered).
TEST(Svgf, TheGuideIsTheGBuffersNormalsAndDepthSlopes) {
  const GBuffer g = scene();
  const SvgfGuide s = svgf_guide(g);
  auto in = [&](int a, int b) {
    return a >= 0 && b >= 0 && a < g.width && b < g.height && g.covered(g.index(a, b));
  };
  auto slope = [&](size_t p, int a0, int b0, int a1, int b1) {
    const bool lo = in(a0, b0), hi = in(a1, b1);
    if (!g.covered(p)) return 0.0f;
    if (lo && hi) return 0.5f * (g.depth[g.index(a1, b1)] - g.depth[g.index(a0, b0)]);
    if (hi) return g.depth[g.index(a1, b1)] - g.depth[p];
    if (lo) return g.depth[p] - g.depth[g.index(a0, b0)];
    return 0.0f;
  };
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      const float c = g.covered(p) ? 1.0f : 0.0f;
      ASSERT_EQ(s.covered[p], c) << i << " " << j;
      ASSERT_EQ(s.nx[p], c * g.normal[p].x) << i << " " << j;
      ASSERT_EQ(s.ny[p], c * g.normal[p].y) << i << " " << j;
      ASSERT_EQ(s.nz[p], c * g.normal[p].z) << i << " " << j;
      ASSERT_EQ(s.depth[p], g.depth[p]) << i << " " << j;
      ASSERT_EQ(s.grad_x[p], slope(p, i - 1, j, i + 1, j)) << i << " " << j;
      ASSERT_EQ(s.grad_y[p], slope(p, i, j - 1, i, j + 1)) << i << " " << j;
    }
}

// Both ways of w_n: by squarings (sigma_n = 128) and by exp and log (sigma_n = 100).
TEST(Svgf, TheRowLoopsGiveThePixelLoopsBits) {
  const GBuffer g = scene();
  const SvgfGuide guide = svgf_guide(g);
  const Signal x = signal(g);
  for (double sigma_n : {128.0, 100.0}) {
    const std::vector<float> a = fast(guide, x, settings(sigma_n)),
                             b = reference(guide, x, settings(sigma_n), fast_exp, fast_log,
                                           fast_weight);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k)
      ASSERT_EQ(a[k], b[k]) << "sigma_n " << sigma_n << ": " << k;
  }
}

// The variance's spatial estimate runs over the short histories of a row only: single pixels at
// both ends of a row (two runs, 35 pixels apart), a run across the middle, and rows with none
// give the pixel loops' bits.
TEST(Svgf, TheVarianceOfScatteredShortHistoriesIsThePixelLoopsBits) {
  const GBuffer g = scene();
  const SvgfGuide guide = svgf_guide(g);
  Signal x = signal(g);
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      if (x.length[p] == 0.0f) continue;
      const bool ends = j % 3 == 0 && (i == 1 || i == g.width - 1);
      const bool middle = j % 5 == 1 && i > 14 && i < 22;
      x.length[p] = ends || middle ? 2.0f : 8.0f;
    }
  const SvgfSettings s = settings();
  EXPECT_EQ(svgf_variance(guide, x.moment1, x.moment2, x.length, s),
            reference_variance(guide, x, s, fast_exp, fast_log));
}

TEST(Svgf, OneThreadGivesTheBitsOfMany) {
  const GBuffer g = scene();
  const Signal x = signal(g);
  std::vector<float> one, many;
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 8);
  tbb::task_arena(1).execute([&] { one = fast(svgf_guide(g), x); });
  tbb::task_arena(8).execute([&] { many = fast(svgf_guide(g), x); });
  EXPECT_EQ(one, many);
}

// The tap loops compiled for AVX2 and AVX-512 (svgf_taps.cpp, run where the CPU has them) give
// the bits of the baseline's (SSE2), so the result does not depend on the CPU: no fused
// multiply-add, the same operations in the same order in every lane. Shown failing with the
// AVX-512 version compiled with FMA and -ffp-contract=fast.
TEST(Svgf, EveryInstructionSetGivesTheBaselineBits) {
  const GBuffer g = scene();
  const SvgfGuide guide = svgf_guide(g);
  const Signal x = signal(g);
  const SimdIsa best = simd_best_isa();
  if (best == SimdIsa::baseline)
    GTEST_SKIP() << "neither AVX2 nor AVX-512 on this CPU (or this compiler builds the baseline "
                    "only): nothing to compare the baseline's bits with";
  for (double sigma_n : {128.0, 100.0}) {
    set_simd_isa(SimdIsa::baseline);
    const std::vector<float> baseline = fast(guide, x, settings(sigma_n));
    for (SimdIsa isa : {SimdIsa::avx2, SimdIsa::avx512}) {
      if (isa > best) {
        std::printf("%s: not on this CPU\n", simd_isa_name(isa));
        continue;
      }
      set_simd_isa(isa);
      const bool same = fast(guide, x, settings(sigma_n)) == baseline;
      EXPECT_TRUE(same) << simd_isa_name(isa) << ", sigma_n " << sigma_n;
      std::printf("%s, sigma_n %g: %s\n", simd_isa_name(isa), sigma_n,
                  same ? "the baseline's bits" : "other bits");
    }
  }
  set_simd_isa(best);
}

// Against libm's exp and log and the paper's divisions (the filter before svgf_math.h): each
// weight moves by a few float ulps (2 from exp, 1 from each reciprocal, sigma_n times 2 ulp of
// log(n_p . n_q), which is tiny near 1, or 7 squarings' roundings, 2^7 - 1 half-ulps at most, for
// sigma_n = 128), so each pass's weighted mean moves by about 1e-6 of the spread of its taps; five
// passes compound that to a few 1e-6. The bound, 1e-5, is a few times what this scene shows, far
// below a 1-ray pixel's noise (0.5).
// A weight below what a float's square can hold is flushed, as every thread of the a-trous pass
// flushes denormals (svgf_math.h: they cost a microcode assist per operation). A flat 9 x 9 plane,
// every value 0 but 7e-9 two pixels right of the centre, every variance 0 but that pixel's 1: the
// centre's luminance denominator is about 1e-10 (its 3x3 variance is 0), so that tap's weight is
// about 1e-20, and its square times the variance a denormal float. Flushed, the centre's variance
// is 0; unflushed it was 6.7e-41.
TEST(Svgf, AWeightTooSmallToSquareAddsNothing) {
  GBuffer g;
  g.width = g.height = 9;
  g.coverage.assign(g.pixel_count(), 1.0f);
  g.depth.assign(g.pixel_count(), 1.0f);
  g.normal.assign(g.pixel_count(), glm::vec3(0, 0, 1));
  const SvgfGuide guide = svgf_guide(g);
  std::vector<float> value(g.pixel_count(), 0.0f), variance(g.pixel_count(), 0.0f);
  value[g.index(6, 4)] = 7e-9f;
  variance[g.index(6, 4)] = 1.0f;
  atrous_iteration(guide, 1, settings(), value, variance);
  EXPECT_EQ(variance[g.index(4, 4)], 0.0f);
  EXPECT_EQ(value[g.index(4, 4)], 0.0f);
  EXPECT_GT(variance[g.index(6, 4)], 0.0f);  // the pixel itself keeps its own
}

TEST(Svgf, WithinABoundOfLibm) {
  const GBuffer g = scene();
  const SvgfGuide guide = svgf_guide(g);
  const Signal x = signal(g);
  for (double sigma_n : {128.0, 100.0}) {
    const std::vector<float> a = fast(guide, x, settings(sigma_n));
    const std::vector<float> b = reference(
        guide, x, settings(sigma_n), [](float e) { return std::exp(e); },
        [](float v) { return std::log(v); }, libm_weight);
    double worst = 0.0;
    for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(double(a[k]) - b[k]));
    EXPECT_LE(worst, 1e-5) << "sigma_n " << sigma_n;
    std::printf("sigma_n %g: largest difference from libm's exp and log: %.3g\n", sigma_n, worst);
  }
}

}  // namespace
}  // namespace aoeval
