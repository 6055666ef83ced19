// Same bits on every platform: no fused multiply-add contraction (GCC and Clang contract a * b + c
// by default wherever the CPU has FMA, e.g. on every ARM64), even where the build lacks
// -ffp-contract=off. Include it first, before any other header, so that the inlined glm code is
// covered too; it applies to the rest of the translation unit (hence no include guard is needed).
#pragma once
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif
