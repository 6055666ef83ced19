// Where a secondary ray may start: shared by the reference and every ray-casting estimator, so a
// surface point means the same to both (and neither depends on the other).
#pragma once

#include <glm/vec3.hpp>

namespace aoeval {

// The offset of a ray origin along Ng: large enough to clear the G-buffer position's rounding error
// (barycentric interpolation: a few ulps of the coordinates' magnitude), small against any feature.
float origin_offset(const glm::vec3& position, float scene_extent);

}  // namespace aoeval
