// SVGF's tap loops (svgf.h, eqs. 1-5 and §4.2), each one tap of the kernel over a span of a row,
// compiled for x86-64's baseline (SSE2), AVX2 and AVX-512 (svgf_taps.cpp); svgf.cpp runs the
// widest this CPU has (estimators/simd_isa.h). Every version does the same float operations in the
// same order (no FMA: -ffp-contract=off; element-wise loops): the same bits on every CPU
// (svgf_test).
#pragma once

#include <cstddef>

#include "estimators/rtao/svgf.h"
#include "estimators/simd_isa.h"

namespace aoeval {

// The guide's arrays as raw pointers, so that the row loops vectorise.
struct GuideRows {
  const float *nx, *ny, *nz, *z, *gx, *gy, *cov;
  explicit GuideRows(const SvgfGuide& g)
      : nx(g.nx.data()),
        ny(g.ny.data()),
        nz(g.nz.data()),
        z(g.depth.data()),
        gx(g.grad_x.data()),
        gy(g.grad_y.data()),
        cov(g.covered.data()) {}
};

// The per-tap constants of the variance estimate's depth and normal weights.
struct TapGeometry {
  float dx, dy, sigma_z, sigma_n;
};

// Running sums of a row: h w c, h^2 w^2 Var and h w (a-trous), w, w m1 and w m2 (variance).
struct Sums {
  float* __restrict sw, * __restrict sc, * __restrict sv;
};
struct MomentSums {
  double* __restrict sw, * __restrict s1, * __restrict s2;
};

// One tap of the a-trous kernel, q = p + shift: its weight h, eq. 3's negated reciprocal
// denominator per pixel of row p for its offset (depth_reciprocals) and sigma_n (eq. 4).
struct AtrousTap {
  ptrdiff_t shift;
  float hk;
  const float* inv_depth;
  float sigma_n;
};

// One row of the a-trous kernel: its taps' weights h (kx = -2..2), their spacing, the offset of its
// row from p's (dy x width), eq. 3's negated reciprocal denominators of its taps (the centre's
// unused) and sigma_n.
struct AtrousRow {
  float hk[5];
  int step;
  ptrdiff_t row_shift;
  const float* inv_depth[5];
  float sigma_n;
};

// w_n = (n_p . n_q)^sigma_n by squarings where sigma_n = 2^k, k <= kMaxSquarings (the default 128
// takes 7 multiplies), else by exp and log.
constexpr int kMaxSquarings = 10;

struct SvgfTaps {
  // The 3x3 blur's tap at q = p + shift for pixels [i0, i1) of a row: weight kw where q is
  // covered (cov_q, var_q: the row shifted to q).
  void (*blur)(const float* cov_q, const float* var_q, float kw, float* sw, float* sv, int i0,
               int i1);
  // One a-trous tap (eqs. 1-5) for pixels [i0, i1) of row `row` (its first pixel's index):
  // accumulates h w_i c(q), h^2 w_i^2 Var(q) (eq. 2's numerator) and h w_i; rl is the negated
  // reciprocal of eq. 5's denominator per pixel of the row.
  void (*atrous)(const GuideRows& gr, ptrdiff_t row, const AtrousTap& t, const float* c,
                 const float* var, const float* rl, Sums out, int i0, int i1);
  // The five taps of kernel row k as five atrous calls would add them, for pixels [i0, i1) whose
  // taps all lie inside the row (the centre tap where k.row_shift = 0).
  void (*atrous_row)(const GuideRows& gr, ptrdiff_t row, const AtrousRow& k, const float* c,
                     const float* var, const float* rl, Sums out, int i0, int i1);
  // One tap of the spatial variance estimate (§4.2): accumulates w, w m1(q) and w m2(q).
  void (*variance)(const GuideRows& gr, ptrdiff_t row, ptrdiff_t shift, const TapGeometry& t,
                   const float* m1, const float* m2, MomentSums out, int i0, int i1);
  // -1 / (sigma_z |grad z(p) . (dx, dy)| + 1e-6 z(p)) (eq. 3's denominator) for pixels [i0, i1).
  void (*depth_reciprocals)(const GuideRows& gr, ptrdiff_t row, float dx, float dy, float sigma_z,
                            float* out, int i0, int i1);
  // -1 / (sigma_l sqrt(sv / sw) + 1e-10) (eq. 5's denominator from the 3x3 blur's sums) where
  // cov > 0.5, else -1.
  void (*luminance_reciprocals)(const float* cov, const float* sw, const float* sv, float sigma_l,
                                float* rl, int i0, int i1);
  // Eqs. 1-2: out_c = clamp(sc / sw, 0, 1), out_var = sv / sw^2 where cov > 0.5 (else unchanged).
  void (*finish)(const float* cov, const float* sw, const float* sc, const float* sv, float* out_c,
                 float* out_var, int i0, int i1);
};

// The tap loops compiled for `isa`, their w_n for sigma_n.
const SvgfTaps& svgf_taps(SimdIsa isa, double sigma_n);

}  // namespace aoeval
