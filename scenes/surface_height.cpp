#include "scenes/surface_height.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace aoeval {
namespace {

double cross2(const glm::dvec3& u, const glm::dvec3& v) {
  return u.x * v.z - u.z * v.x;
}

}  // namespace

void SurfaceHeight::cell_range(double lo, double hi, double origin, double cell, int n, int& first,
                               int& last) const {
  first = std::clamp(static_cast<int>(std::floor((lo - origin) / cell)), 0, n - 1);
  last = std::clamp(static_cast<int>(std::floor((hi - origin) / cell)), 0, n - 1);
}

SurfaceHeight::SurfaceHeight(const TriangleMesh& mesh) {
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    if (cross2(b - a, c - a) == 0.0) continue;  // edge-on from above
    a_.push_back(a);
    b_.push_back(b);
    c_.push_back(c);
  }
  if (a_.empty()) return;
  double x1 = -INFINITY, z1 = -INFINITY;
  x0_ = z0_ = INFINITY;
  for (size_t i = 0; i < a_.size(); ++i)
    for (const glm::dvec3& p : {a_[i], b_[i], c_[i]}) {
      x0_ = std::min(x0_, p.x), z0_ = std::min(z0_, p.z);
      x1 = std::max(x1, p.x), z1 = std::max(z1, p.z);
    }
  const double w = std::max(x1 - x0_, 1e-30), d = std::max(z1 - z0_, 1e-30);
  const double cells = std::clamp(static_cast<double>(a_.size()), 1.0, 16777216.0);
  nx_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(cells * w / d))), 1, 4096);
  nz_ = std::clamp(static_cast<int>(std::ceil(cells / nx_)), 1, 4096);
  cell_x_ = w / nx_;
  cell_z_ = d / nz_;
  std::vector<uint32_t> count(static_cast<size_t>(nx_) * nz_ + 1, 0);
  auto visit = [&](size_t i, auto&& f) {
    int i0, i1, j0, j1;
    cell_range(std::min({a_[i].x, b_[i].x, c_[i].x}), std::max({a_[i].x, b_[i].x, c_[i].x}), x0_,
               cell_x_, nx_, i0, i1);
    cell_range(std::min({a_[i].z, b_[i].z, c_[i].z}), std::max({a_[i].z, b_[i].z, c_[i].z}), z0_,
               cell_z_, nz_, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int k = i0; k <= i1; ++k) f(static_cast<size_t>(j) * nx_ + k);
  };
  for (size_t i = 0; i < a_.size(); ++i) visit(i, [&](size_t cell) { ++count[cell + 1]; });
  for (size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  start_ = count;
  items_.resize(count.back());
  for (size_t i = 0; i < a_.size(); ++i)
    visit(i, [&](size_t cell) { items_[count[cell]++] = static_cast<uint32_t>(i); });
}

std::optional<SurfacePoint> SurfaceHeight::at(double x, double z) const {
  if (a_.empty() || !std::isfinite(x) || !std::isfinite(z)) return std::nullopt;
  int i, i1, j, j1;
  cell_range(x, x, x0_, cell_x_, nx_, i, i1);
  cell_range(z, z, z0_, cell_z_, nz_, j, j1);
  const size_t cell = static_cast<size_t>(j) * nx_ + i;
  std::optional<SurfacePoint> best;
  constexpr double kEdge = 1e-9;  // barycentric slack: a point on a shared edge is covered
  for (uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
    const uint32_t t = items_[k];
    const glm::dvec3 &a = a_[t], e1 = b_[t] - a, e2 = c_[t] - a, p(x - a.x, 0.0, z - a.z);
    const double den = cross2(e1, e2);
    const double u = cross2(p, e2) / den, v = cross2(e1, p) / den;
    if (u < -kEdge || v < -kEdge || u + v > 1.0 + kEdge) continue;
    const double y = a.y + u * e1.y + v * e2.y;
    if (best && !(y > best->y)) continue;
    glm::dvec3 nrm = glm::normalize(glm::cross(e1, e2));
    if (nrm.y < 0.0) nrm = -nrm;
    best = SurfacePoint{static_cast<float>(y), glm::vec3(nrm)};
  }
  return best;
}

}  // namespace aoeval
