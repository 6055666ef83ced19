// The CPU side of the shared kernel (hbao_kernel.glsl): the images it reads, as plain arrays, and
// their accessors. A translation unit that runs the kernel includes this header, defines
// hbao_depth() in a namespace of its own (named uniquely across the program: the kernel's
// functions are not inline), includes the kernel there, then hbao_cpu_kernel_end.h (hbao_cpu.cpp,
// raymarch_ssao.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "estimators/hbao_split/hbao_split.h"
#include "estimators/screen_space/glsl_compat.h"

namespace aoeval::hbao_glsl {
using namespace aoeval::glsl;  // the GLSL spellings (screen_space/glsl_compat.h)

struct HbaoImages {
  int width = 0;
  size_t pixels = 0;
  const float* depth = nullptr;
  const vec3* normal = nullptr;
  const vec3* random = nullptr;  // tile x tile
  int tile = 1;
  const vec2* directions = nullptr;
  const float* raw_ao = nullptr;
  float* horizon = nullptr;  // Nd planes of width x height: H(theta_d)^2
  uint64_t* fetches = nullptr;
};

inline size_t pixel_of(const HbaoImages& img, int i, int j) {
  return static_cast<size_t>(j) * static_cast<size_t>(img.width) + static_cast<size_t>(i);
}
inline vec3 hbao_normal(const HbaoImages& img, int i, int j) {
  return img.normal[pixel_of(img, i, j)];
}
inline vec3 hbao_random(const HbaoImages& img, int i, int j) {
  return img.random[static_cast<size_t>((j % img.tile) * img.tile + i % img.tile)];
}
inline vec2 hbao_direction(const HbaoImages& img, int d) {
  return img.directions[d];
}
inline float hbao_raw_ao(const HbaoImages& img, int i, int j) {
  return img.raw_ao[pixel_of(img, i, j)];
}
inline void hbao_store_horizon(const HbaoImages& img, int i, int j, int d, float h) {
  img.horizon[static_cast<size_t>(d) * img.pixels + pixel_of(img, i, j)] = h;
}
inline float hbao_load_horizon(const HbaoImages& img, int i, int j, int d) {
  return img.horizon[static_cast<size_t>(d) * img.pixels + pixel_of(img, i, j)];
}

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
// The images reach the kernel as GLSL globals (bindings) and as an explicit first argument in C++.
#define HBAO_IMAGES_PARAM const HbaoImages &img,
#define HBAO_IMAGES_ARG img,
