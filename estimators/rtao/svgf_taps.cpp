// SVGF's tap loops (svgf_taps.inc) compiled once per instruction set (svgf_taps.h).
#include "estimators/rtao/svgf_taps.h"

#include <cmath>
#include <cstddef>

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

const SvgfTaps& svgf_taps(SimdIsa isa) {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)  // GCC's #pragma target
  if (isa == SimdIsa::avx512) return svgf_avx512::kTaps;
  if (isa == SimdIsa::avx2) return svgf_avx2::kTaps;
#endif
  return svgf_baseline::kTaps;
}

}  // namespace aoeval
