#include "estimators/tree_proxies/far_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <string>

#include "base/errors.h"

namespace aoeval {

namespace {

constexpr float kMaxExponent = 88.0f;  // exp(-88) is below float's smallest normal

// The 26 stored directions (index 13, the zero vector, stays 0).
std::array<glm::vec3, FarGrid::kDirections> directions() {
  std::array<glm::vec3, FarGrid::kDirections> d{};
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (i != 0 || j != 0 || k != 0)
          d[static_cast<size_t>((i + 1) * 9 + (j + 1) * 3 + k + 1)] = glm::normalize(
              glm::vec3(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k)));
  return d;
}

// The normal's cube face (major axis) and its bilinear taps over that face's 3 x 3 texels.
struct DirectionTaps {
  int index[4];
  float weight[4];
  int count;
};
DirectionTaps direction_taps(const glm::vec3& n) {
  const glm::vec3 m = glm::abs(n);
  const int major = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
  const int a = (major + 1) % 3, b = (major + 2) % 3;
  const float len = std::max(m[major], 1e-30f);
  const float s = std::clamp(n[a] / len, -1.0f, 1.0f), t = std::clamp(n[b] / len, -1.0f, 1.0f);
  const int s0 = s < 0.0f ? -1 : 0, t0 = t < 0.0f ? -1 : 0;
  const float fs = s - static_cast<float>(s0), ft = t - static_cast<float>(t0);
  DirectionTaps taps{};
  for (int c = 0; c < 4; ++c) {
    int v[3];
    v[major] = n[major] < 0.0f ? -1 : 1;
    v[a] = s0 + (c & 1);
    v[b] = t0 + (c >> 1);
    taps.index[c] = (v[0] + 1) * 9 + (v[1] + 1) * 3 + v[2] + 1;
    taps.weight[c] = ((c & 1) ? fs : 1.0f - fs) * ((c >> 1) ? ft : 1.0f - ft);
  }
  // Only the taps that weigh (a normal along an axis, flat ground, has one).
  taps.count = 0;
  for (int c = 0; c < 4; ++c)
    if (taps.weight[c] != 0.0f) {
      taps.index[taps.count] = taps.index[c];
      taps.weight[taps.count++] = taps.weight[c];
    }
  return taps;
}

// Per tree or node of `far`: 1 / |G n_k| for the stored directions.
using InverseWidths = std::array<float, FarGrid::kDirections>;
InverseWidths inverse_widths(const glm::mat3& g, const std::array<glm::vec3, 27>& dirs) {
  InverseWidths w{};
  for (size_t k = 0; k < dirs.size(); ++k)
    if (k != 13) w[k] = 1.0f / glm::length(g * dirs[k]);
  return w;
}

// Nodes along one axis, in double: a tiny cell gives a count past int's range (refused by the
// caller before any cast).
double axis_nodes(double extent, double cell) {
  return std::max(2.0, std::ceil(std::max(extent, 0.0) / cell) + 1.0);
}

// floor(v) as an index clamped to [lo, hi]; v may be far beyond int's range or not finite.
int clamped_floor(double v, int lo, int hi) {
  if (!(v >= lo)) return lo;
  return v >= hi ? hi : static_cast<int>(std::floor(v));
}

}  // namespace

float FarGrid::near_weight(float d, float inner, float outer) {
  if (d <= inner) return 1.0f;
  if (d >= outer) return 0.0f;
  const float t = (d - inner) / (outer - inner);
  return 1.0f - t * t * (3.0f - 2.0f * t);
}

void FarGrid::build(const std::vector<hegeman::UnitMap>& occluders, const FarField& far,
                    const Bounds& region, double cell, double near, bool horizon) {
  occluders_ = occluders;
  horizon_ = horizon;
  values_.clear();
  start_.clear();
  items_.clear();
  nx_ = ny_ = nz_ = 0;
  if (!(cell > 0.0) || occluders.size() < kMinTrees) return;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-lo);
  for (const hegeman::UnitMap& m : occluders) {
    lo = glm::min(lo, m.center);
    hi = glm::max(hi, m.center);
  }
  near_ = static_cast<float>(near);
  cell_ = static_cast<float>(cell);
  // Per tree: s is 1 within max(R/2, r_max,t), so on its own leaves too, and 0 from R/2 beyond
  // (the own tree's interpolated far part is not 0 there: far_grid.h).
  inner_.resize(occluders.size());
  float widest = near_;
  for (size_t t = 0; t < occluders.size(); ++t) {
    inner_[t] = std::max(0.5f * near_, occluders[t].max_radius);
    widest = std::max(widest, inner_[t] + 0.5f * near_);
  }
  // The trees' box widened by their outer radius, and by at least 8 cells (where the far part
  // still changes), within the scene's bounds; pixels beyond use FarField::visibility.
  const glm::vec3 widen(std::max(widest, 8.0f * cell_));
  // The scene's bounds a cell wider: G-buffer positions on its faces are rounded either way.
  origin_ = glm::max(lo - widen, region.lower - cell_);
  const glm::vec3 top = glm::min(hi + widen, region.upper + cell_);
  if (!(top.x >= origin_.x && top.y >= origin_.y && top.z >= origin_.z)) return;
  const glm::dvec3 extent = glm::dvec3(top) - glm::dvec3(origin_);
  const double ax = axis_nodes(extent.x, cell), ay = axis_nodes(extent.y, cell),
               az = axis_nodes(extent.z, cell);
  const double count = ax * ay * az;
  if (!(count <= static_cast<double>(kMaxNodes))) {
    char nodes[64];
    std::snprintf(nodes, sizeof nodes, "%g gives %.3g", cell, count);
    throw InputError(std::string("far_grid_cell ") + nodes +
                     " far-field nodes over the trees (more than " + std::to_string(kMaxNodes) +
                     "); use a larger cell");
  }
  nx_ = static_cast<int>(ax);
  ny_ = static_cast<int>(ay);
  nz_ = static_cast<int>(az);
  upper_ = origin_ + cell_ * glm::vec3(nx_ - 1, ny_ - 1, nz_ - 1);

  // The near lists, before the far sums so that a refusal comes first: every tree whose centre is
  // within its outer radius (in x-z) of a column's rectangle.
  const size_t columns = static_cast<size_t>(nx_ - 1) * static_cast<size_t>(nz_ - 1);
  start_.assign(columns + 1, 0);
  auto each_column = [&](const glm::vec3& centre, float reach, auto&& f) {
    const int i0 = clamped_floor((double{centre.x} - reach - origin_.x) / cell_, 0, nx_ - 2);
    const int i1 = clamped_floor((double{centre.x} + reach - origin_.x) / cell_, -1, nx_ - 2);
    const int k0 = clamped_floor((double{centre.z} - reach - origin_.z) / cell_, 0, nz_ - 2);
    const int k1 = clamped_floor((double{centre.z} + reach - origin_.z) / cell_, -1, nz_ - 2);
    for (int k = k0; k <= k1; ++k)
      for (int i = i0; i <= i1; ++i) {
        const float x0 = origin_.x + cell_ * static_cast<float>(i), z0 = origin_.z + cell_ * k;
        const float dx = std::max({x0 - centre.x, 0.0f, centre.x - x0 - cell_});
        const float dz = std::max({z0 - centre.z, 0.0f, centre.z - z0 - cell_});
        if (dx * dx + dz * dz <= reach * reach)
          f(static_cast<size_t>(k) * static_cast<size_t>(nx_ - 1) + static_cast<size_t>(i));
      }
  };
  // Counted in size_t and refused as soon as the total passes kMaxNearEntries: one tree adds at
  // most `columns` (< kMaxNodes) entries, so the total and start_'s uint32_t never wrap, and the
  // count stops within a tree of the limit (the whole count can reach 10^10 at R = 10^6).
  size_t total = 0;
  for (size_t t = 0; t < occluders.size(); ++t) {
    each_column(occluders[t].center, inner_[t] + 0.5f * near_, [&](size_t c) {
      ++start_[c + 1];
      ++total;
    });
    if (total > kMaxNearEntries) {
      const double estimate = static_cast<double>(total) * static_cast<double>(occluders.size()) /
                              static_cast<double>(t + 1);
      char about[64];
      std::snprintf(about, sizeof about, "%g puts more than %zu trees (about %.3g)", near,
                    kMaxNearEntries, estimate);
      nx_ = 0;  // covers nothing
      throw InputError(std::string("far_near_radius ") + about +
                       " into the grid's near lists; use a smaller radius, or far_grid_cell=0 "
                       "for no grid");
    }
  }
  for (size_t c = 0; c < columns; ++c) start_[c + 1] += start_[c];
  items_.resize(start_.back());
  near_trees_.resize(start_.back());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t t = 0; t < occluders.size(); ++t)
    each_column(occluders[t].center, inner_[t] + 0.5f * near_, [&](size_t c) {
      const float outer = inner_[t] + 0.5f * near_;
      near_trees_[fill[c]] = {occluders[t].center, outer * outer};
      items_[fill[c]++] = static_cast<uint32_t>(t);
    });

  // The far sums at the nodes.
  const auto dirs = directions();
  std::vector<InverseWidths> tree_widths(occluders.size()), node_widths(far.nodes());
  for (size_t t = 0; t < occluders.size(); ++t)
    tree_widths[t] = inverse_widths(far.normal_map(false, static_cast<uint32_t>(t)), dirs);
  for (size_t b = 0; b < far.nodes(); ++b)
    node_widths[b] = inverse_widths(far.normal_map(true, static_cast<uint32_t>(b)), dirs);
  values_.assign(static_cast<size_t>(nx_) * ny_ * nz_ * kDirections, 0.0f);
  tbb::parallel_for(0, nz_ * ny_, [&](int row) {
    const int k = row / ny_, j = row % ny_;
    for (int i = 0; i < nx_; ++i) {
      const glm::vec3 p = origin_ + cell_ * glm::vec3(i, j, k);
      std::array<double, kDirections> sum{};
      far.gather(p, widest, [&](const glm::vec3& q, float d2, float a, bool node, uint32_t id) {
        const float w =
            node ? 1.0f : 1.0f - near_weight(std::sqrt(d2), inner_[id], inner_[id] + 0.5f * near_);
        if (w <= 0.0f) return;
        const InverseWidths& width = node ? node_widths[id] : tree_widths[id];
        for (size_t dir = 0; dir < kDirections; ++dir) {
          if (dir == 13) continue;
          float h = 1.0f;
          if (horizon_) {
            const float u = glm::dot(q, dirs[dir]) * width[dir];
            h = u >= 1.0f ? 1.0f : (u <= -1.0f ? 0.0f : hegeman::above_horizon_fraction(u));
          }
          const float ad = a * h;
          // A node is exp(-a_N) (far_field.h); a tree its own factor 1 - a_t.
          sum[dir] += node ? ad : w * (ad >= 1.0f ? kMaxExponent : -std::log1p(-ad));
        }
      });
      float* out = &values_[node_index(i, j, k) * kDirections];
      for (size_t dir = 0; dir < kDirections; ++dir)
        out[dir] = static_cast<float>(std::min<double>(sum[dir], kMaxExponent));
    }
  });
}

bool FarGrid::covers(const glm::vec3& x) const {
  return nx_ > 0 && x.x >= origin_.x && x.x <= upper_.x && x.y >= origin_.y && x.y <= upper_.y &&
         x.z >= origin_.z && x.z <= upper_.z;
}

size_t FarGrid::column(const glm::vec3& x) const {
  const int i = std::min(nx_ - 2, static_cast<int>((x.x - origin_.x) / cell_));
  const int k = std::min(nz_ - 2, static_cast<int>((x.z - origin_.z) / cell_));
  return static_cast<size_t>(k) * static_cast<size_t>(nx_ - 1) + static_cast<size_t>(i);
}

float FarGrid::far_occlusion(const glm::vec3& x, const glm::vec3& n) const {
  const glm::vec3 f = (x - origin_) / cell_;
  const int i = std::min(nx_ - 2, static_cast<int>(f.x));
  const int j = std::min(ny_ - 2, static_cast<int>(f.y));
  const int k = std::min(nz_ - 2, static_cast<int>(f.z));
  const glm::vec3 w = f - glm::vec3(i, j, k);
  const DirectionTaps taps = direction_taps(n);
  const size_t sx = kDirections, sy = sx * static_cast<size_t>(nx_),
               sz = sy * static_cast<size_t>(ny_);
  const float* base = &values_[node_index(i, j, k) * kDirections];
  const size_t offset[8] = {0, sx, sy, sx + sy, sz, sx + sz, sy + sz, sx + sy + sz};
  const float wx[2] = {1.0f - w.x, w.x}, wy[2] = {1.0f - w.y, w.y}, wz[2] = {1.0f - w.z, w.z};
  float sum = 0.0f;
  for (int d = 0; d < taps.count; ++d) {
    const float* v = base + taps.index[d];
    float at = 0.0f;
    for (int c = 0; c < 8; ++c) at += wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2] * v[offset[c]];
    sum += taps.weight[d] * at;
  }
  return sum;
}

float FarGrid::visibility(const glm::vec3& x, const glm::vec3& n, int skip) const {
  float v = 1.0f, exponent = far_occlusion(x, n);
  const size_t c = column(x);
  for (uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
    const glm::vec4& near = near_trees_[k];
    const float dx = near.x - x.x, dy = near.y - x.y, dz = near.z - x.z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 >= near.w) continue;
    const uint32_t t = items_[k];
    if (static_cast<int>(t) == skip) continue;
    const float vt = hegeman::large_occluder_visibility(x, n, occluders_[t], horizon_);
    if (d2 <= inner_[t] * inner_[t]) {
      v *= vt;
    } else if (vt <= 0.0f) {
      return 0.0f;
    } else {
      exponent -= near_weight(std::sqrt(d2), inner_[t], inner_[t] + 0.5f * near_) * std::log(vt);
    }
  }
  return v * std::exp(-exponent);
}

}  // namespace aoeval
