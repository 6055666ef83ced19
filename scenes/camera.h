// The pinhole camera of CONTRACT §3: vertical field of view in degrees, pixel (i, j) sampled at its
// centre (i + 0.5, j + 0.5), row 0 at the top, right-handed world with +Y up.
#pragma once

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scenes/scene.h"

namespace aoeval {

struct Camera {
  glm::vec3 eye{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit, towards the target
  glm::vec3 right{1.0f, 0.0f, 0.0f};     // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward and right
  float tan_half_fov_y = 0.41421356f;
  int width = 1;
  int height = 1;
  // A sequence frame's sub-pixel sample offset in pixels (x right, y down; CONTRACT §10 "halton"
  // jitter): pixel (i, j) is sampled at (i + 0.5 + jitter.x, j + 0.5 + jitter.y). Zero for stills.
  glm::vec2 jitter{0.0f};

  // Unit direction through the (jittered) centre of pixel (i, j).
  glm::vec3 direction(int i, int j) const {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const float x =
        (2.0f * (static_cast<float>(i) + 0.5f + jitter.x) / static_cast<float>(width) - 1.0f) *
        tan_half_fov_y * aspect;
    const float y =
        (1.0f - 2.0f * (static_cast<float>(j) + 0.5f + jitter.y) / static_cast<float>(height)) *
        tan_half_fov_y;
    return glm::normalize(forward + x * right + y * up);
  }
  // Linear view depth (distance along `forward`) of a hit at ray distance t along direction(i, j).
  float view_depth(const glm::vec3& dir, float t) const { return t * glm::dot(dir, forward); }
};

// The camera of `view` at a resolution (the view's own when width/height are 0).
Camera make_camera(const View& view, int width = 0, int height = 0);

}  // namespace aoeval
