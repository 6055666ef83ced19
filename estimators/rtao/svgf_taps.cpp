// SVGF's tap loops (svgf_taps.inc) compiled once per instruction set (svgf_taps.h).
#include "estimators/rtao/svgf_taps.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include "estimators/rtao/svgf_math.h"

namespace aoeval {

namespace svgf_baseline {
#include "estimators/rtao/svgf_taps.inc"
}  // namespace svgf_baseline

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)  // GCC's #pragma target
#pragma GCC push_options
#pragma GCC target("avx2")
namespace svgf_avx2 {
#include "estimators/rtao/svgf_taps.inc"
}  // namespace svgf_avx2
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,prefer-vector-width=512")
namespace svgf_avx512 {
#include "estimators/rtao/svgf_taps.inc"
}  // namespace svgf_avx512
#pragma GCC pop_options
#endif

namespace {
// 1 + k where sigma_n = 2^k, 0 <= k <= kMaxSquarings; else 0.
int squarings_slot(double sigma_n) {
  for (int k = 0; k <= kMaxSquarings; ++k)
    if (sigma_n == static_cast<double>(1 << k)) return 1 + k;
  return 0;
}
}  // namespace

const SvgfTaps& svgf_taps(SimdIsa isa, double sigma_n) {
  const int slot = squarings_slot(sigma_n);
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)  // GCC's #pragma target
  if (isa == SimdIsa::avx512) return svgf_avx512::kTaps[slot];
  if (isa == SimdIsa::avx2) return svgf_avx2::kTaps[slot];
#endif
  return svgf_baseline::kTaps[slot];
}

}  // namespace aoeval
