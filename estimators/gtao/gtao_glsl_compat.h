// The few GLSL spellings that gtao_kernel.glsl uses, defined for C++ so that the one kernel source
// compiles as both the CPU twin (gtao_cpu.cpp) and the Vulkan compute shaders: the same float
// operations in the same order. The build has -ffp-contract=off; the GLSL side marks its
// arithmetic `precise` (SPIR-V NoContraction), which forbids fused multiply-adds there too. The
// kernel calls no transcendental function (gtao_kernel.glsl says how), only + - * / and sqrt, which
// IEEE 754 rounds correctly on both sides. Include it, then the accessors, then the kernel, then
// gtao_cpu_kernel_end.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace aoeval::gtao_glsl {

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
// GLSL's floor() of a float image coordinate as an int texel index, defined for every input:
// NaN and values beyond int's range (a point near the eye plane projects anywhere) give a
// coordinate outside the image, which the kernel then ignores.
inline int gtao_floor(float u) {
  if (!(u > -1.0e6f && u < 1.0e6f)) return -1000000;
  return static_cast<int>(std::floor(u));
}

}  // namespace aoeval::gtao_glsl

// GLSL's `precise` has no C++ spelling: -ffp-contract=off does its job.
#define precise
// Parameters written by the callee: `out T` in GLSL, a reference in C++.
#define GTAO_OUT(T) T&
// The images reach the kernel as GLSL globals (bindings) and as an explicit first argument in C++.
#define GTAO_IMAGES_PARAM const GtaoImages &img,
#define GTAO_IMAGES_ARG img,
