// Shading points for the tree_proxies tests: random positions over a square of half-side
// `extent` (every other one within `near` of the origin when near > 0), heights `y0` +- `dy`,
// normals up, tilted by up to `tilt` in x and z. Deterministic (fixed seed). And sphere_map.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <random>
#include <vector>

#include "estimators/tree_proxies/hegeman_model.h"

namespace aoeval::testutil {

struct Pixel {
  glm::vec3 x, n;
};

// The large occluder of a sphere of radius r at c.
inline hegeman::UnitMap sphere_map(const glm::vec3& c, float r) {
  Ellipsoid e;
  e.center = c;
  e.radii = glm::vec3(r);
  return hegeman::make_unit_map(e);
}

inline std::vector<Pixel> random_pixels(size_t count, float extent, float near, float tilt,
                                        float y0, float dy) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Pixel> out;
  for (size_t k = 0; k < count; ++k) {
    const float spread = near > 0.0f && k % 2 == 0 ? near : extent;
    const glm::vec3 n = glm::normalize(glm::vec3(tilt * u(rng), 1.0f, tilt * u(rng)));
    out.push_back({glm::vec3(spread * u(rng), y0 + dy * u(rng), spread * u(rng)), n});
  }
  return out;
}

}  // namespace aoeval::testutil
