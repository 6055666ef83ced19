#include "scenes/surface_height.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace aoeval {
namespace {

double cross2(const glm::dvec3& u, const glm::dvec3& v) {
  return u.x * v.z - u.z * v.x;
}

// The cell of v along one axis, clamped to the grid (a point on the far edge is in the last cell),
// in double before the cast: a query far off the grid would overflow int.
int cell_of(double v, double origin, double cell, int n) {
  return static_cast<int>(std::clamp(std::floor((v - origin) / cell), 0.0, n - 1.0));
}

}  // namespace

SurfaceHeight::SurfaceHeight(const TriangleMesh& mesh, const std::optional<Footprint>& within) {
  std::vector<glm::dvec2> lo, hi;  // the kept triangles' (x, z) boxes
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    const glm::dvec3 e1 = b - a, e2 = c - a;
    const double den = cross2(e1, e2);
    if (den == 0.0) continue;  // edge-on from above
    const glm::dvec2 box_lo(std::min({a.x, b.x, c.x}), std::min({a.z, b.z, c.z}));
    const glm::dvec2 box_hi(std::max({a.x, b.x, c.x}), std::max({a.z, b.z, c.z}));
    if (within && (box_hi.x < within->x0 || box_lo.x > within->x1 || box_hi.y < within->z0 ||
                   box_lo.y > within->z1))
      continue;  // wholly outside the footprint asked for
    triangles_.push_back(
        {a.x, a.z, a.y, e2.z / den, -e2.x / den, -e1.z / den, e1.x / den, e1.y, e2.y});
    glm::dvec3 n = glm::normalize(glm::cross(e1, e2));
    normals_.emplace_back(n.y < 0.0 ? -n : n);
    lo.push_back(box_lo);
    hi.push_back(box_hi);
  }
  if (triangles_.empty()) return;
  glm::dvec2 all_lo = lo[0], all_hi = hi[0];
  for (size_t i = 0; i < lo.size(); ++i)
    all_lo = glm::min(all_lo, lo[i]), all_hi = glm::max(all_hi, hi[i]);
  x0_ = all_lo.x, z0_ = all_lo.y;
  const double w = std::max(all_hi.x - x0_, 1e-30), d = std::max(all_hi.y - z0_, 1e-30);
  // About two cells a triangle: a cell then holds a few triangles' boxes.
  const double cells = std::clamp(2.0 * static_cast<double>(triangles_.size()), 1.0, 16777216.0);
  nx_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(cells * w / d))), 1, 4096);
  nz_ = std::clamp(static_cast<int>(std::ceil(cells / nx_)), 1, 4096);
  cell_x_ = w / nx_;
  cell_z_ = d / nz_;
  std::vector<uint32_t> count(static_cast<size_t>(nx_) * nz_ + 1, 0);
  // A box whose far side lies on a cell boundary is not listed in the cell beyond it: a query
  // there takes the cell's own triangles, one of which holds the shared edge (edges count as
  // covered). A regular height field's triangles then sit in the cells of their own grid cell
  // alone (2 candidates a query instead of up to 8; the query was 15 % of a forest-10k frame, 14 %
  // after this).
  auto span = [](double from, double to, double origin, double cell, int n, int& first, int& last) {
    first = cell_of(from, origin, cell, n);
    last = std::clamp(static_cast<int>(std::ceil((to - origin) / cell)) - 1, first, n - 1);
  };
  auto visit = [&](size_t i, auto&& f) {
    int i0, i1, j0, j1;
    span(lo[i].x, hi[i].x, x0_, cell_x_, nx_, i0, i1);
    span(lo[i].y, hi[i].y, z0_, cell_z_, nz_, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int k = i0; k <= i1; ++k) f(static_cast<size_t>(j) * nx_ + k);
  };
  for (size_t i = 0; i < triangles_.size(); ++i) visit(i, [&](size_t cell) { ++count[cell + 1]; });
  for (size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  start_ = count;
  items_.resize(count.back());
  for (size_t i = 0; i < triangles_.size(); ++i)
    visit(i, [&](size_t cell) { items_[count[cell]++] = static_cast<uint32_t>(i); });
}

std::optional<SurfacePoint> SurfaceHeight::at(double x, double z) const {
  if (triangles_.empty() || !std::isfinite(x) || !std::isfinite(z)) return std::nullopt;
  const size_t cell = static_cast<size_t>(cell_of(z, z0_, cell_z_, nz_)) * nx_ +
                      static_cast<size_t>(cell_of(x, x0_, cell_x_, nx_));
  constexpr double kEdge = 1e-9;  // barycentric slack: a point on a shared edge is covered
  double best_y = -INFINITY;
  uint32_t best = UINT32_MAX;
  for (uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
    const Triangle& t = triangles_[items_[k]];
    const double px = x - t.ax, pz = z - t.az;
    const double u = px * t.ux + pz * t.uz, v = px * t.vx + pz * t.vz;
    if (u < -kEdge || v < -kEdge || u + v > 1.0 + kEdge) continue;
    const double y = t.ay + u * t.dy1 + v * t.dy2;
    if (y > best_y) best_y = y, best = items_[k];
  }
  if (best == UINT32_MAX) return std::nullopt;
  return SurfacePoint{static_cast<float>(best_y), normals_[best]};
}

}  // namespace aoeval
