// The GLSL spellings that the screen-space kernels use (hbao_kernel.glsl, gtao_kernel.glsl,
// half_res.glsl, eye_normal.glsl), defined for C++ so that one kernel source compiles as both the
// CPU twin and the Vulkan compute shaders: the same float operations in the same order. The build
// has -ffp-contract=off; the GLSL side marks its arithmetic `precise` (SPIR-V NoContraction), which
// forbids fused multiply-adds there too.
//
// One shim for every kernel: a kernel's C++ namespace takes the spellings with
// `using namespace aoeval::glsl;` (or lives inside aoeval::glsl), and its parameters written or
// read-and-written by the callee are GLSL_OUT(T) / GLSL_INOUT(T), which the GLSL side defines as
// `out T` / `inout T` (hbao_common.glsl, gtao_common.glsl). What differs between the kernels (their
// image accessors, the <KERNEL>_IMAGES_PARAM / _ARG macros that pass them, a texel helper) is
// the kernel's own, in its *_cpu_kernel.h. A translation unit includes this header, the
// accessors, the kernel, then glsl_compat_end.h (through the kernel's own end header, if any),
// which takes the macros back: one kernel per translation unit.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace aoeval::glsl {

using glm::ivec2;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using std::abs;
using std::max;
using std::min;
using std::sqrt;

inline float clamp(float x, float lo, float hi) {
  return min(max(x, lo), hi);
}
inline int clamp(int x, int lo, int hi) {
  return min(max(x, lo), hi);
}

}  // namespace aoeval::glsl

// GLSL's `precise` has no C++ spelling: -ffp-contract=off does its job.
#define precise
// Parameters written by the callee: `out T` in GLSL, a reference in C++.
#define GLSL_OUT(T) T&
// Parameters read and written by the callee: `inout T` in GLSL, a reference in C++.
#define GLSL_INOUT(T) T&
