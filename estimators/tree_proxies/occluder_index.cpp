#include "estimators/tree_proxies/occluder_index.h"

#include <limits>

namespace aoeval {

void OccluderIndex::build(const std::vector<hegeman::UnitMap>& occluders, double epsilon) {
  const size_t n = occluders.size();
  centers_.resize(n);
  radius2_.resize(n);
  all_ = !(epsilon > 0.0) || n == 0;
  reach_ = 0.0f;
  float x1 = 0.0f, z1 = 0.0f;
  x0_ = z0_ = 0.0f;
  for (size_t t = 0; t < n; ++t) {
    const hegeman::UnitMap& m = occluders[t];
    centers_[t] = m.center;
    const double r2 = static_cast<double>(m.max_radius) * m.max_radius / (2.0 * epsilon);
    radius2_[t] = static_cast<float>(std::min<double>(r2, std::numeric_limits<float>::max()));
    reach_ = std::max(reach_, std::sqrt(radius2_[t]));
    x0_ = t == 0 ? m.center.x : std::min(x0_, m.center.x);
    z0_ = t == 0 ? m.center.z : std::min(z0_, m.center.z);
    x1 = t == 0 ? m.center.x : std::max(x1, m.center.x);
    z1 = t == 0 ? m.center.z : std::max(z1, m.center.z);
  }
  start_.clear();
  items_.clear();
  if (all_) return;
  // Cells of half the largest reach (a query then spans about 5 x 5 cells), but no finer than
  // 1/1024 of the footprint and no more than about 4 cells per occluder.
  const float ex = x1 - x0_, ez = z1 - z0_;
  cell_ = std::max({reach_ / 2.0f, std::max(ex, ez) / 1024.0f,
                    std::sqrt(ex * ez / static_cast<float>(4 * n + 16)), 1e-6f});
  nx_ = static_cast<int>(ex / cell_) + 1;
  nz_ = static_cast<int>(ez / cell_) + 1;
  const size_t cells = static_cast<size_t>(nx_) * static_cast<size_t>(nz_);
  std::vector<size_t> cell(n);
  start_.assign(cells + 1, 0);
  for (size_t t = 0; t < n; ++t) {
    cell[t] = static_cast<size_t>(cell_of(centers_[t].z, z0_, nz_)) * static_cast<size_t>(nx_) +
              static_cast<size_t>(cell_of(centers_[t].x, x0_, nx_));
    ++start_[cell[t] + 1];
  }
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(n);
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t t = 0; t < n; ++t) items_[fill[cell[t]]++] = static_cast<uint32_t>(t);
}

}  // namespace aoeval
