#include "estimators/rtao/svgf.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>

#include "estimators/rtao/svgf_math.h"
#include "estimators/rtao/svgf_taps.h"

namespace aoeval {

namespace {

// The B3-spline's 1D taps (Dammertz et al. 2010; Schied et al. 2017 §4.3): h = outer product.
constexpr float kB3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};

// Rows per task: a tile of 4 rows x the image's width (640 pixels: 25 taps of 7 channels stay in
// cache), enough tasks to balance 16 cores on 480 rows.
constexpr int kTileRows = 4;

// Runs body(j0, j1) over tiles of rows in parallel.
template <class Body>
void for_each_row_tile(int height, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, kTileRows),
                    [&](const tbb::blocked_range<int>& r) { body(r.begin(), r.end()); });
}

// The pixels i of a row whose tap i + dx lies inside [0, width).
inline int first_inside(int dx) {
  return std::max(0, -dx);
}
inline int end_inside(int width, int dx) {
  return std::min(width, width - dx);
}

// The covered span [lo, hi) of a row (lo = hi: none): the pixels outside it are background, which
// neither filters nor is filtered, so the row loops skip them.
struct Span {
  int lo, hi;
  int begin(int i0) const { return std::max(lo, i0); }
  int end(int i1) const { return std::min(hi, i1); }
};
Span covered_span(const float* cov, int w) {
  int lo = 0, hi = w;
  while (lo < w && !(cov[lo] > 0.5f)) ++lo;
  while (hi > lo && !(cov[hi - 1] > 0.5f)) --hi;
  return {lo, hi};
}

// The runs of a row whose covered pixels have a history shorter than `frames` (the variance's
// spatial estimate), in order; runs less than kRunGap pixels apart are joined (a loop's start
// costs more than a few pixels).
constexpr int kRunGap = 32;
std::vector<Span> short_runs(const float* cov, const float* len, float frames, int w) {
  std::vector<Span> runs;
  for (int i = 0; i < w; ++i) {
    if (!(cov[i] > 0.5f && len[i] < frames)) continue;
    if (!runs.empty() && i - runs.back().hi < kRunGap)
      runs.back().hi = i + 1;
    else
      runs.push_back({i, i + 1});
  }
  return runs;
}

// The 24 offsets of the 5x5 kernel in 12 mirror pairs (kx, ky) ~ (-kx, -ky), which share eq. 3's
// denominator: the index of (kx, ky)'s pair.
constexpr int kMirrorOffsets = 12;
int mirror_offset(int kx, int ky) {
  if (ky < 0 || (ky == 0 && kx < 0)) kx = -kx, ky = -ky;
  return ky == 0 ? kx - 1 : 2 + (ky - 1) * 5 + (kx + 2);
}

}  // namespace

SvgfGuide svgf_guide(const GBuffer& g) {
  SvgfGuide s;
  svgf_guide(g, s);
  return s;
}

// The central difference of depth z at pixel i along a line of pixels (previous / next: z_lo,
// z_hi, whether each is covered), a one-sided difference where only one is, 0 where neither is.
inline float slope(bool lo, bool hi, float z_lo, float z, float z_hi) {
  if (lo && hi) return 0.5f * (z_hi - z_lo);
  if (hi) return z_hi - z;
  if (lo) return z - z_lo;
  return 0.0f;
}

void svgf_guide(const GBuffer& g, SvgfGuide& s) {
  s.width = g.width;
  s.height = g.height;
  const int w = g.width, h = g.height;
  const size_t n = g.pixel_count();
  // Every element is written below: a guide of the same size is reused without clearing.
  for (std::vector<float>* v : {&s.nx, &s.ny, &s.nz, &s.depth, &s.grad_x, &s.grad_y, &s.covered})
    v->resize(n);
  for_each_row_tile(h, [&](int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
      const size_t row = static_cast<size_t>(j) * w;
      const float* cov = g.coverage.data() + row;
      const float* z = g.depth.data() + row;
      // The rows above and below (themselves where there is none: never read then).
      const size_t up = j > 0 ? row - w : row, down = j + 1 < h ? row + w : row;
      const bool has_up = j > 0, has_down = j + 1 < h;
      for (int i = 0; i < w; ++i) {
        const size_t p = row + i;
        const bool c = is_covered(cov[i]);
        // n_p . n_q = 0 where either is uncovered.
        s.nx[p] = c ? g.normal[p].x : 0.0f;
        s.ny[p] = c ? g.normal[p].y : 0.0f;
        s.nz[p] = c ? g.normal[p].z : 0.0f;
        s.depth[p] = z[i];
        s.covered[p] = c ? 1.0f : 0.0f;
        const bool left = c && i > 0 && is_covered(cov[i - 1]);
        const bool right = c && i + 1 < w && is_covered(cov[i + 1]);
        const bool above = c && has_up && is_covered(g.coverage[up + i]);
        const bool below = c && has_down && is_covered(g.coverage[down + i]);
        s.grad_x[p] = slope(left, right, left ? z[i - 1] : 0.0f, z[i], right ? z[i + 1] : 0.0f);
        s.grad_y[p] = slope(above, below, above ? g.depth[up + i] : 0.0f, z[i],
                            below ? g.depth[down + i] : 0.0f);
      }
    }
  });
}

std::vector<float> svgf_variance(const SvgfGuide& g, const std::vector<float>& moment1,
                                 const std::vector<float>& moment2,
                                 const std::vector<float>& history_length, const SvgfSettings& s) {
  const int w = g.width, rad = s.variance_radius;
  const float frames = static_cast<float>(s.variance_frames);
  const float sigma_z = static_cast<float>(s.sigma_z), sigma_n = static_cast<float>(s.sigma_n);
  const GuideRows gr(g);
  const float *m1 = moment1.data(), *m2 = moment2.data(), *len = history_length.data();
  const SvgfTaps& taps = svgf_taps(simd_isa(), s.sigma_n);
  std::vector<float> variance(static_cast<size_t>(w) * g.height, 0.0f);
  for_each_row_tile(g.height, [&](int j0, int j1) {
    std::vector<double> sw(w), s1(w), s2(w);
    for (int j = j0; j < j1; ++j) {
      const ptrdiff_t row = static_cast<ptrdiff_t>(j) * w;
      // §4.2: the bilateral estimate (7x7 at the paper's radius 3), depth and normal weights
      // only, the taps in row order, over the runs of the row whose history is short (the other
      // pixels read their own moments); the centre's weight is exp(0) = 1. A pixel's sums do not
      // depend on the run it is in: the same bits as over the whole row.
      for (const Span run : short_runs(gr.cov + row, len + row, frames, w)) {
        std::fill(sw.begin() + run.lo, sw.begin() + run.hi, 0.0);
        std::fill(s1.begin() + run.lo, s1.begin() + run.hi, 0.0);
        std::fill(s2.begin() + run.lo, s2.begin() + run.hi, 0.0);
        for (int dy = -rad; dy <= rad; ++dy) {
          if (j + dy < 0 || j + dy >= g.height) continue;
          for (int dx = -rad; dx <= rad; ++dx) {
            const ptrdiff_t shift = static_cast<ptrdiff_t>(dy) * w + dx;
            if (shift == 0) {  // the centre: weight exp(0) = 1
              for (int i = run.lo; i < run.hi; ++i) {
                sw[i] += 1.0;
                s1[i] += m1[row + i];
                s2[i] += m2[row + i];
              }
              continue;
            }
            const TapGeometry geometry{static_cast<float>(dx), static_cast<float>(dy), sigma_z,
                                       sigma_n};
            const int i0 = run.begin(first_inside(dx)), i1 = run.end(end_inside(w, dx));
            if (i0 < i1)
              taps.variance(gr, row, shift, geometry, m1, m2, {sw.data(), s1.data(), s2.data()}, i0,
                            i1);
          }
        }
      }
      for (int i = 0; i < w; ++i) {
        const ptrdiff_t p = row + i;
        if (!(gr.cov[p] > 0.5f)) continue;
        double a = m1[p], b = m2[p];
        if (len[p] < frames) {
          a = s1[i] / sw[i];  // sw >= 1: the centre tap
          b = s2[i] / sw[i];
        }
        variance[p] = static_cast<float>(std::max(0.0, b - a * a));
      }
    }
  });
  return variance;
}

void atrous_iteration(const SvgfGuide& g, int step, const SvgfSettings& s,
                      std::vector<float>& value, std::vector<float>& variance) {
  // The input, 0 where uncovered, so that a tap of weight 0 adds 0 whatever was there.
  std::vector<float> in_value(value.size()), in_variance(variance.size());
  for_each_row_tile(g.height, [&](int j0, int j1) {
    const size_t p0 = static_cast<size_t>(j0) * g.width, p1 = static_cast<size_t>(j1) * g.width;
    for (size_t p = p0; p < p1; ++p) {  // bit-mask selects: a vectorised loop
      const bool covered = g.covered[p] > 0.5f;
      in_value[p] = keep(covered, value[p]);
      in_variance[p] = keep(covered, variance[p]);
    }
  });
  const int w = g.width, h = g.height;
  const float sigma_z = static_cast<float>(s.sigma_z), sigma_n = static_cast<float>(s.sigma_n);
  const float sigma_l = static_cast<float>(s.sigma_l);
  const GuideRows gr(g);
  const float *c = in_value.data(), *var = in_variance.data();
  float *out_c = value.data(), *out_var = variance.data();
  const SvgfTaps& taps = svgf_taps(simd_isa(), s.sigma_n);
  for_each_row_tile(h, [&](int j0, int j1) {
    const FlushDenormals flush;  // the same arithmetic on every thread (svgf_math.h)
    // A row's sums, eq. 5's reciprocals and eq. 3's per mirror offset, read and written over the
    // row's covered span only (not cleared beyond it).
    const std::unique_ptr<float[]> buffer(new float[(4 + kMirrorOffsets) * static_cast<size_t>(w)]);
    float *sw = buffer.get(), *sc = sw + w, *sv = sc + w, *rl = sv + w, *rz = rl + w;
    auto inv_depth = [&](int kx, int ky) { return rz + mirror_offset(kx, ky) * w; };
    for (int j = j0; j < j1; ++j) {
      const ptrdiff_t row = static_cast<ptrdiff_t>(j) * w;
      const Span span = covered_span(gr.cov + row, w);
      if (span.lo == span.hi) continue;
      // g_3x3 of eq. 5: the variance under a 3x3 Gaussian (1/4, 1/2, 1/4)^2 over covered pixels,
      // then the reciprocal of the luminance weight's denominator sigma_l sqrt(g_3x3(Var)) + eps.
      constexpr float k[3] = {0.25f, 0.5f, 0.25f};
      std::fill(sw + span.lo, sw + span.hi, 0.0f);
      std::fill(sv + span.lo, sv + span.hi, 0.0f);
      for (int dy = -1; dy <= 1; ++dy) {
        if (j + dy < 0 || j + dy >= h) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const ptrdiff_t shift = static_cast<ptrdiff_t>(dy) * w + dx;
          const float kw = k[dx + 1] * k[dy + 1];
          taps.blur(gr.cov + row + shift, var + row + shift, kw, sw, sv,
                    span.begin(first_inside(dx)), span.end(end_inside(w, dx)));
        }
      }
      // Only the span's pixels are read below.
      taps.luminance_reciprocals(gr.cov + row, sw, sv, sigma_l, rl, span.lo, span.hi);
      // Eq. 3's reciprocal denominators, one per pair of mirror offsets, for the kernel rows that
      // lie in the image.
      for (int ky = 0; ky <= 2; ++ky) {
        const int dy = ky * step;
        if ((j + dy < 0 || j + dy >= h) && (j - dy < 0 || j - dy >= h)) continue;
        for (int kx = ky == 0 ? 1 : -2; kx <= 2; ++kx)
          taps.depth_reciprocals(gr, row, static_cast<float>(kx * step), static_cast<float>(dy),
                                 sigma_z, inv_depth(kx, ky), span.lo, span.hi);
      }
      // Eqs. 1-2 over the 5x5 taps in the kernel's order; the centre's weight is exp(0) = 1. The
      // pixels whose taps all lie inside the row, [in_lo, in_hi), take a kernel row in one loop;
      // the others tap by tap (the same order of sums).
      std::fill(sw + span.lo, sw + span.hi, 0.0f);
      std::fill(sc + span.lo, sc + span.hi, 0.0f);
      std::fill(sv + span.lo, sv + span.hi, 0.0f);
      const int in_lo = std::max(span.lo, 2 * step);
      const int in_hi = std::max(in_lo, std::min(span.hi, w - 2 * step));
      const Sums sums{sw, sc, sv};
      for (int ky = -2; ky <= 2; ++ky) {
        const int dy = ky * step;
        if (j + dy < 0 || j + dy >= h) continue;
        AtrousRow kernel_row{{}, step, static_cast<ptrdiff_t>(dy) * w, {}, sigma_n};
        for (int kx = -2; kx <= 2; ++kx) {
          kernel_row.hk[kx + 2] = kB3[kx + 2] * kB3[ky + 2];
          if (kx != 0 || ky != 0) kernel_row.inv_depth[kx + 2] = inv_depth(kx, ky);
        }
        if (in_lo < in_hi) taps.atrous_row(gr, row, kernel_row, c, var, rl, sums, in_lo, in_hi);
        for (int kx = -2; kx <= 2; ++kx) {
          const int dx = kx * step;
          const AtrousTap tap{static_cast<ptrdiff_t>(dy) * w + dx, kernel_row.hk[kx + 2],
                              kernel_row.inv_depth[kx + 2], sigma_n};
          // This tap's pixels outside [in_lo, in_hi).
          const int b = span.begin(first_inside(dx)), e = span.end(end_inside(w, dx));
          for (const auto& [i0, i1] :
               {std::pair{b, std::min(e, in_lo)}, std::pair{std::max(b, in_hi), e}}) {
            if (i0 >= i1) continue;
            if (tap.shift == 0) {
              for (int i = i0; i < i1; ++i) {
                sw[i] += tap.hk;
                sc[i] += tap.hk * c[row + i];
                sv[i] += tap.hk * tap.hk * var[row + i];
              }
              continue;
            }
            taps.atrous(gr, row, tap, c, var, rl, sums, i0, i1);
          }
        }
      }
      taps.finish(gr.cov + row, sw, sc, sv, out_c + row, out_var + row, span.lo, span.hi);
    }
  });
}

}  // namespace aoeval
