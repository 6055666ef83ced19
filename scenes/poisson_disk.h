// Poisson-disk points for the "poisson-disk" placer (issue 45, README "Instanced objects"):
// exactly `count` points in a width x depth rectangle, no two closer than `spacing` x
// sqrt(width x depth / count), by seeded dart throwing over a background grid (one point per cell
// of side min_distance / sqrt 2). Deterministic from the seed. Dart throwing saturates near 0.55
// disk coverage, i.e. spacing ~ 0.83; up to 0.75 it places `count` points in a few tries each.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <optional>
#include <vector>

namespace aoeval {

inline constexpr double kMaxPoissonSpacing = 0.75;

// The points in acceptance order, relative to the rectangle's lower corner; nullopt when
// 64 x count darts did not place them all.
std::optional<std::vector<glm::dvec2>> poisson_disk_points(uint64_t seed, size_t count,
                                                           double width, double depth,
                                                           double spacing);

}  // namespace aoeval
