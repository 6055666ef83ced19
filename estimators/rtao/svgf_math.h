// exp and log for SVGF's edge-stopping weights (svgf.h, eqs. 3-5) as branch-free inline float code
// that the compiler vectorises inside a row loop (a libm call per tap cannot be): Cody-Waite range
// reduction and the polynomials of Cephes' expf and logf (Moshier 1992, "Methods and Programs for
// Mathematical Functions"), expf's shortened by two terms. Within 2 ulp of libm over the ranges
// SVGF uses (svgf_test: FastExp.WithinTwoUlpOfLibm, FastLog.WithinTwoUlpOfLibm):
//  - svgf_exp(x) for x <= 0 (every SVGF exponent is): 0 below about -87.7 (where expf leaves the
//    normal floats; a weight under 1e-38 beside a centre tap of 9/64) and at -infinity.
//  - svgf_log(x) for normal x in (0, 1] (a cosine of two normals, capped at 1).
// Deterministic: IEEE float operations in a fixed order, the same bits on every thread.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace aoeval {

// v where ok, else +0, by a bit mask: a select the compiler keeps branch-free in a vector loop.
// Flush-to-zero and denormals-are-zero on this thread while in scope (x86's MXCSR; elsewhere
// nothing). The a-trous weights span many decades: (n_p . n_q)^128 of a crease, exp of a large
// depth or luminance difference once the variance has shrunk over the passes, and their squares in
// eq. 2 fall below FLT_MIN, where every operation on the result took a microcode assist (the
// passes at steps 8 and 16 cost 1.4-1.8 x the first). A weight that small adds nothing to sums
// whose centre tap is at least 9/64; flushed, it adds 0.
class FlushDenormals {
 public:
#if defined(__SSE__) || defined(__x86_64__)
  FlushDenormals() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | 0x8040u);
  }
  ~FlushDenormals() {
    _mm_setcsr(saved_);
  }

 private:
  unsigned saved_;
#endif
};

inline float keep(bool ok, float v) {
  return std::bit_cast<float>(std::bit_cast<uint32_t>(v) & (0u - static_cast<uint32_t>(ok)));
}

inline float svgf_exp(float x) {
  // Below -88 (and at -infinity), x = -88 gives n = -127 below, whose 2^n is +0: for x <= 0 the
  // smaller magnitude has the smaller bits as an unsigned integer, and an integer min vectorises
  // where a float ?: does not (-ftrapping-math). A NaN is not defined (SVGF's exponents are NaN
  // only on taps whose weight is masked to 0).
  const float xc =
      std::bit_cast<float>(std::min(std::bit_cast<uint32_t>(x), std::bit_cast<uint32_t>(-88.0f)));
  // n = round(x / ln 2) by the 1.5 2^23 trick (exact in round-to-nearest), r = x - n ln 2 in two
  // parts (Cody-Waite), so |r| <= ln 2 / 2.
  const float shifted = xc * 1.44269504088896341f + 12582912.0f;  // 1.5 2^23 + n, ulp 1
  const float n = shifted - 12582912.0f;
  float r = xc - n * 0.693359375f;
  r = r - n * -2.12194440e-4f;
  const float r2 = r * r;
  // exp(r) = 1 + r + r^2 p(r), p cubic: its relative error is 1.05e-7 on |r| <= ln 2 / 2 (fitted
  // by iteratively reweighted least squares towards the minimax; Cephes' expf takes a quintic p).
  float p = 8.312530800149888e-3f;
  p = p * r + 4.1890125564609096e-2f;
  p = p * r + 1.666711444180814e-1f;
  p = p * r + 4.9999231674419164e-1f;
  p = p * r2 + r + 1.0f;
  // 2^n for n in [-127, 0]: a normal float's exponent field, or +0 for n = -127; n + 127 read
  // from the bits of 1.5 2^23 + n (no float-to-integer conversion).
  const float scale = std::bit_cast<float>(
      (std::bit_cast<int32_t>(shifted) - (std::bit_cast<int32_t>(12582912.0f) - 127)) << 23);
  return p * scale;
}

inline float svgf_log(float x) {
  const int32_t bits = std::bit_cast<int32_t>(x);
  int32_t e = (bits >> 23) - 127;
  float m = std::bit_cast<float>((bits & 0x007fffff) | 0x3f800000);  // [1, 2)
  const bool high = m > 1.41421356f;                                 // fold to [sqrt(1/2), sqrt(2))
  m = m * (keep(high, 0.5f) + keep(!high, 1.0f));
  e = e + static_cast<int32_t>(high);
  const float f = m - 1.0f, z = f * f, fe = static_cast<float>(e);
  float y = 7.0376836292e-2f;
  y = y * f - 1.1514610310e-1f;
  y = y * f + 1.1676998740e-1f;
  y = y * f - 1.2420140846e-1f;
  y = y * f + 1.4249322787e-1f;
  y = y * f - 1.6668057665e-1f;
  y = y * f + 2.0000714765e-1f;
  y = y * f - 2.4999993993e-1f;
  y = y * f + 3.3333331174e-1f;
  y = y * f * z;
  y = y + fe * -2.12194440e-4f;
  y = y - 0.5f * z;
  return (f + y) + fe * 0.693359375f;
}

}  // namespace aoeval
