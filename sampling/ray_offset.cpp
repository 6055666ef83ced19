#include "sampling/ray_offset.h"

#include <algorithm>
#include <cmath>

namespace aoeval {

float origin_offset(const glm::vec3& p, float scene_extent) {
  const float magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  // 2^-14 relative: ~500 ulps of the position, far above barycentric rounding (a few ulps of the
  // vertices' magnitude, bounded by the scene extent) and far below any modelled feature.
  return std::ldexp(std::max(magnitude, 0.01f * scene_extent), -14);
}

}  // namespace aoeval
