#include "scenes/poisson_disk.h"

#include <algorithm>
#include <cmath>

#include "scenes/random.h"

namespace aoeval {

std::optional<std::vector<glm::dvec2>> poisson_disk_points(uint64_t seed, size_t count,
                                                           double width, double depth,
                                                           double spacing) {
  const double r = spacing * std::sqrt(width * depth / static_cast<double>(count));
  const double cell = r / std::sqrt(2.0);  // at most one accepted point per cell
  const auto nx = static_cast<size_t>(std::ceil(width / cell)) + 1;
  const auto nz = static_cast<size_t>(std::ceil(depth / cell)) + 1;
  std::vector<int64_t> grid(nx * nz, -1);
  std::vector<glm::dvec2> points;
  points.reserve(count);
  SplitMix64 g(mix_seed(seed, count, 0x9D15C));
  const size_t darts = 64 * count;
  for (size_t d = 0; d < darts && points.size() < count; ++d) {
    const glm::dvec2 p(width * g.uniform_double(), depth * g.uniform_double());
    const auto ci = static_cast<size_t>(p.x / cell), cj = static_cast<size_t>(p.y / cell);
    bool free = grid[cj * nx + ci] < 0;
    // A point within r lies at most 2 cells away (r = sqrt 2 cells).
    for (size_t j = cj >= 2 ? cj - 2 : 0; free && j <= std::min(cj + 2, nz - 1); ++j)
      for (size_t i = ci >= 2 ? ci - 2 : 0; free && i <= std::min(ci + 2, nx - 1); ++i) {
        const int64_t q = grid[j * nx + i];
        if (q < 0) continue;
        const glm::dvec2 e = points[static_cast<size_t>(q)] - p;
        free = e.x * e.x + e.y * e.y >= r * r;
      }
    if (!free) continue;
    grid[cj * nx + ci] = static_cast<int64_t>(points.size());
    points.push_back(p);
  }
  if (points.size() < count) return std::nullopt;
  return points;
}

}  // namespace aoeval
