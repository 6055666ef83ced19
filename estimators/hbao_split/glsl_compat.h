// The few GLSL spellings that hbao_kernel.glsl uses, defined for C++ so that the one kernel source
// compiles as both the CPU twin and the Vulkan compute shaders: the same float operations in the
// same order (the build has -ffp-contract=off; the GLSL side marks its arithmetic `precise`, which
// forbids fused multiply-adds there too). Include it inside a namespace, then the accessors, then
// the kernel.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aoeval::hbao_glsl {

using glm::ivec2;
using glm::vec2;
using glm::vec3;
using std::abs;
using std::max;
using std::min;
using std::sqrt;

// The texel index of image coordinate u, clamped into [0, size) (hbao_kernel.glsl): GLSL's
// clamp(int(u), 0, size - 1) for every finite u, without C++'s undefined conversion of a float
// beyond int's range (a point near the eye plane projects anywhere) or of NaN (taken as 0).
inline int hbao_texel(float u, int size) {
  if (!(u >= 0.0f)) return 0;
  if (u >= static_cast<float>(size - 1)) return size - 1;
  return static_cast<int>(u);
}

}  // namespace aoeval::hbao_glsl

// The CPU runs one pixel at a time: loops may stop early (hbao_kernel.glsl, hbao_march).
#define HBAO_SCALAR_DEVICE 1
// GLSL's `precise` (SPIR-V NoContraction) has no C++ spelling: -ffp-contract=off does its job.
#define precise
// Parameters written by the callee: `out T` in GLSL, a reference in C++.
#define HBAO_OUT(T) T&
// Parameters read and written by the callee: `inout T` in GLSL, a reference in C++.
#define HBAO_INOUT(T) T&
// The images reach the kernel as GLSL globals (bindings) and as an explicit first argument in C++.
#define HBAO_IMAGES_PARAM const HbaoImages &img,
#define HBAO_IMAGES_ARG img,
