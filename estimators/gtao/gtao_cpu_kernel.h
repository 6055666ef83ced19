// The CPU side of the shared kernel (gtao_kernel.glsl): the images it reads, as plain arrays, and
// their accessors. gtao_cpu.cpp includes this header, the kernel, then gtao_cpu_kernel_end.h.
#pragma once

#include <cstddef>

#include "estimators/gtao/gtao.h"
#include "estimators/screen_space/glsl_compat.h"

// The images reach the kernel as GLSL globals (bindings) and as an explicit first argument in C++.
#define GTAO_IMAGES_PARAM const GtaoImages &img,
#define GTAO_IMAGES_ARG img,

namespace aoeval::gtao_glsl {
using namespace aoeval::glsl;  // the GLSL spellings (screen_space/glsl_compat.h)

// GLSL's floor() of a float image coordinate as an int texel index, defined for every input:
// NaN and values beyond int's range (a point near the eye plane projects anywhere) give a
// coordinate outside the image, which the kernel then ignores.
inline int gtao_floor(float u) {
  if (!(u > -1.0e6f && u < 1.0e6f)) return -1000000;
  return static_cast<int>(std::floor(u));
}

struct GtaoImages {
  int width = 0;
  int tile = 1;
  int steps = 1;
  const float* depth = nullptr;
  const vec3* normal = nullptr;
  const vec2* rotation = nullptr;  // tile x tile
  const float* step = nullptr;     // tile x tile x steps
  const vec2* slice = nullptr;
  const float* raw_ao = nullptr;
  const vec3* raw_bent = nullptr;
};

inline size_t gtao_pixel_of(const GtaoImages& img, int i, int j) {
  return static_cast<size_t>(j) * static_cast<size_t>(img.width) + static_cast<size_t>(i);
}
inline size_t gtao_texel_of(const GtaoImages& img, int i, int j) {
  return static_cast<size_t>((j % img.tile) * img.tile + i % img.tile);
}
inline float gtao_depth(const GtaoImages& img, int i, int j) {
  return img.depth[gtao_pixel_of(img, i, j)];
}
inline vec3 gtao_normal(const GtaoImages& img, int i, int j) {
  return img.normal[gtao_pixel_of(img, i, j)];
}
inline vec2 gtao_rotation(const GtaoImages& img, int i, int j) {
  return img.rotation[gtao_texel_of(img, i, j)];
}
inline float gtao_step(const GtaoImages& img, int i, int j, int k) {
  return img
      .step[gtao_texel_of(img, i, j) * static_cast<size_t>(img.steps) + static_cast<size_t>(k)];
}
inline vec2 gtao_slice(const GtaoImages& img, int s) {
  return img.slice[s];
}
inline float gtao_raw_ao(const GtaoImages& img, int i, int j) {
  return img.raw_ao[gtao_pixel_of(img, i, j)];
}
inline vec3 gtao_raw_bent(const GtaoImages& img, int i, int j) {
  return img.raw_bent[gtao_pixel_of(img, i, j)];
}

#include "estimators/gtao/gtao_kernel.glsl"

}  // namespace aoeval::gtao_glsl

#include "estimators/gtao/gtao_cpu_kernel_end.h"
