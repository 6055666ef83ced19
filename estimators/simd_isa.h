// Which instruction set the CPU estimators' vectorised row loops run with. A loop compiled for
// x86-64's baseline (SSE2), AVX2 and AVX-512 (16 floats a vector; svgf_taps.cpp shows how) is run
// in the widest this CPU has. Every version must do the same IEEE float operations in the same
// order, so that the bits do not depend on the CPU: the build compiles with -ffp-contract=off (no
// fused multiply-add is formed, whatever the target), the loops are element-wise (no reduction
// whose order a vector width would change), and division and sqrt are correctly rounded in every
// instruction set (svgf_test: Svgf.EveryInstructionSetGivesTheBaselineBits).
#pragma once

#include <atomic>

namespace aoeval {

enum class SimdIsa { baseline = 0, avx2 = 1, avx512 = 2 };

inline const char* simd_isa_name(SimdIsa isa) {
  return isa == SimdIsa::avx512 ? "avx512" : isa == SimdIsa::avx2 ? "avx2" : "baseline";
}

// The widest instruction set this CPU (and its OS) supports and this build has versions for: the
// AVX versions are built with GCC's #pragma target only (svgf_taps.cpp), so another compiler's
// build runs the baseline.
inline SimdIsa simd_best_isa() {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  static const SimdIsa best = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f")) return SimdIsa::avx512;
    if (__builtin_cpu_supports("avx2")) return SimdIsa::avx2;
    return SimdIsa::baseline;
  }();
  return best;
#else
  return SimdIsa::baseline;
#endif
}

inline std::atomic<SimdIsa>& simd_isa_choice() {
  static std::atomic<SimdIsa> choice{simd_best_isa()};
  return choice;
}
// The instruction set to run: the best, unless set_simd_isa chose a narrower one.
inline SimdIsa simd_isa() {
  return simd_isa_choice().load(std::memory_order_relaxed);
}
// For tests and measurements: run `isa` from now on (capped at the best this CPU has).
inline void set_simd_isa(SimdIsa isa) {
  simd_isa_choice().store(isa > simd_best_isa() ? simd_best_isa() : isa);
}

}  // namespace aoeval
