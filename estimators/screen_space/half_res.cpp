// Half resolution on the CPU: the frame, the parameter and the upsample (see half_res.h; the
// weights are half_res.glsl's, compiled here as C++).
#include "estimators/screen_space/half_res.h"

#include <glm/vec4.hpp>

#include "estimators/pixel_loops.h"
#include "estimators/screen_space/glsl_compat.h"

namespace aoeval::glsl::half_res {

using half_res_glsl::HalfResConstants;

struct HalfResImages {
  const ScreenSpaceFrame* full = nullptr;
};
inline float halfres_depth(const HalfResImages& img, int i, int j) {
  return img.full->depth[static_cast<size_t>(j) * static_cast<size_t>(img.full->width) +
                         static_cast<size_t>(i)];
}
inline vec3 halfres_normal(const HalfResImages& img, int i, int j) {
  return img.full->normal[static_cast<size_t>(j) * static_cast<size_t>(img.full->width) +
                          static_cast<size_t>(i)];
}

#define HALFRES_IMAGES_PARAM const HalfResImages &img,
#define HALFRES_IMAGES_ARG img,
#include "estimators/screen_space/half_res.glsl"
#undef HALFRES_IMAGES_PARAM
#undef HALFRES_IMAGES_ARG

}  // namespace aoeval::glsl::half_res

#include "estimators/screen_space/glsl_compat_end.h"

namespace aoeval {

namespace {

// sum_k w_k low(candidate k), in the shaders' order; `none` where no candidate is usable.
template <class T>
std::vector<T> upsample(const ScreenSpaceFrame& full, const std::vector<T>& low, T none) {
  namespace hr = glsl::half_res;
  const HalfResConstants c = half_res_constants(full, false);
  const hr::HalfResImages img{&full};
  std::vector<T> out(full.depth.size(), T(0.0f));
  for_each_pixel(full.width, full.height, [&](int x, int y) {
    const size_t p =
        static_cast<size_t>(y) * static_cast<size_t>(full.width) + static_cast<size_t>(x);
    if (!(full.depth[p] > 0.0f)) return;
    const glm::vec4 w = hr::halfres_weights(img, x, y, c);
    if (!(w.x > 0.0f || w.y > 0.0f || w.z > 0.0f || w.w > 0.0f)) {
      out[p] = none;
      return;
    }
    T sum(0.0f);
    for (int k = 0; k < 4; ++k) {
      const glm::ivec2 s = hr::halfres_candidate(x, y, k, c);
      sum += low[static_cast<size_t>(s.y) * static_cast<size_t>(c.low_width) +
                 static_cast<size_t>(s.x)] *
             w[k];
    }
    out[p] = sum;
  });
  return out;
}

}  // namespace

ParamSpec resolution_param() {
  return {
      .name = "resolution",
      .type = ParamType::choice,
      .default_value = "full",
      .min = 0,
      .max = 0,
      .log_scale = false,
      .unit = "",
      .meaning =
          "full: AO at every pixel; half: AO on the half-resolution frame (pixel (2i, 2j) of each "
          "2 x 2 block), then a joint bilateral upsample on depth and normal (half_res.glsl)",
      .choices = {"full", "half"}};
}

bool half_resolution(const ParamSet& params) {
  return params.choice("resolution") == "half";
}

ScreenSpaceFrame half_resolution_shape(const ScreenSpaceFrame& full) {
  ScreenSpaceFrame f;
  f.width = (full.width + 1) / 2;
  f.height = (full.height + 1) / 2;
  f.focal = 0.5f * full.focal;
  // Exact in float: quarters of integers far below 2^22.
  auto shift = [](int n, float own) {
    return 0.25f * static_cast<float>(n) + 0.25f - 0.5f * static_cast<float>(own);
  };
  f.centre_shift =
      glm::vec2(shift(full.width, static_cast<float>(f.width)) + 0.5f * full.centre_shift.x,
                shift(full.height, static_cast<float>(f.height)) + 0.5f * full.centre_shift.y);
  return f;
}

ScreenSpaceFrame half_resolution_frame(const ScreenSpaceFrame& full) {
  ScreenSpaceFrame f = half_resolution_shape(full);
  const size_t n = static_cast<size_t>(f.width) * static_cast<size_t>(f.height);
  f.depth.resize(n);
  f.normal.resize(n);
  for (int j = 0; j < f.height; ++j) {
    for (int i = 0; i < f.width; ++i) {
      const size_t k =
          static_cast<size_t>(j) * static_cast<size_t>(f.width) + static_cast<size_t>(i);
      const size_t s =
          static_cast<size_t>(2 * j) * static_cast<size_t>(full.width) + static_cast<size_t>(2 * i);
      f.depth[k] = full.depth[s];
      f.normal[k] = full.normal[s];
    }
  }
  return f;
}

HalfResConstants half_res_constants(const ScreenSpaceFrame& full, bool vector) {
  HalfResConstants c{};
  c.width = full.width;
  c.height = full.height;
  c.low_width = (full.width + 1) / 2;
  c.low_height = (full.height + 1) / 2;
  c.vector = vector ? 1 : 0;
  return c;
}

std::vector<float> upsample_half_res(const ScreenSpaceFrame& full, const std::vector<float>& low) {
  return upsample(full, low, 1.0f);
}

std::vector<glm::vec3> upsample_half_res(const ScreenSpaceFrame& full,
                                         const std::vector<glm::vec3>& low) {
  return upsample(full, low, glm::vec3(0.0f));
}

}  // namespace aoeval
