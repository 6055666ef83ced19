#include "estimators/tree_proxies/far_field.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numeric>

namespace aoeval {

namespace {

constexpr uint32_t kLeafTrees = 4;

// (A A^T)^(1/2) for A = to_unit^-1, through the orthogonal polar factor U of A (Newton's
// iteration U <- (U + U^-T) / 2), A = P U: P = A U^T. Symmetric, so |P n| = |A^T n| and
// |P^-1 w| = |A^-1 w| whatever the ellipsoid's orientation.
glm::dmat3 left_stretch(const hegeman::UnitMap& m) {
  const glm::dmat3 a = glm::transpose(glm::dmat3(m.normal_map));
  glm::dmat3 u = a;
  for (int k = 0; k < 60; ++k) {
    const glm::dmat3 next = 0.5 * (u + glm::transpose(glm::inverse(u)));
    double change = 0.0;
    for (int i = 0; i < 3; ++i) change = std::max(change, glm::length(next[i] - u[i]));
    u = next;
    if (change < 1e-14) break;
  }
  const glm::dmat3 p = a * glm::transpose(u);
  return 0.5 * (p + glm::transpose(p));
}

// a_N of far_field.h: |B q| h / (2 d^3).
float aggregate_occlusion(const glm::mat3& silhouette, const glm::mat3& normal_map,
                          const glm::vec3& q, float d2, const glm::vec3& n, bool horizon) {
  float a = glm::length(silhouette * q) / (2.0f * d2 * std::sqrt(d2));
  if (!horizon) return a;
  const float u = glm::dot(q, n) / glm::length(normal_map * n);
  return u >= 1.0f ? a : a * hegeman::above_horizon_fraction(u);  // (1 from u = 1 on)
}

}  // namespace

void FarField::build(const std::vector<hegeman::UnitMap>& occluders, double epsilon, double angle) {
  occluders_ = occluders;
  const size_t n = occluders.size();
  cull_ = epsilon > 0.0;
  angle_ = angle;
  silhouette_.resize(n);
  normal_map_.resize(n);
  influence2_.resize(n);
  for (size_t t = 0; t < n; ++t) {
    const hegeman::UnitMap& m = occluders[t];
    const glm::dmat3 p = left_stretch(m);
    silhouette_[t] = glm::mat3(static_cast<double>(m.det) * glm::inverse(p));
    normal_map_[t] = glm::mat3(p);
    const double r2 = static_cast<double>(m.max_radius) * m.max_radius;
    influence2_[t] = cull_ ? static_cast<float>(std::min<double>(r2 / (2.0 * epsilon),
                                                                 std::numeric_limits<float>::max()))
                           : std::numeric_limits<float>::max();
  }
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.clear();
  if (n > 0) build_node(0, static_cast<uint32_t>(n));
  position_.resize(n);
  for (uint32_t k = 0; k < n; ++k) position_[order_[k]] = k;
}

uint32_t FarField::build_node(uint32_t begin, uint32_t end) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.begin = begin;
  node.end = end;
  // Aggregate: w_t = trace(B_t) / 3 (r^2 for a sphere).
  glm::dvec3 center(0.0), lo(std::numeric_limits<double>::max()), hi(-lo);
  glm::dmat3 silhouette(0.0), normal_map(0.0);
  double weight = 0.0;
  for (uint32_t k = begin; k < end; ++k) {
    const uint32_t t = order_[k];
    const glm::dmat3 b(silhouette_[t]);
    const double w = (b[0][0] + b[1][1] + b[2][2]) / 3.0;
    const glm::dvec3 c(occluders_[t].center);
    center += w * c;
    weight += w;
    silhouette += b;
    normal_map += w * glm::dmat3(normal_map_[t]);
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  center /= weight;
  node.center = glm::vec3(center);
  node.silhouette = glm::mat3(silhouette);
  node.normal_map = glm::mat3(normal_map / weight);
  double radius = 0.0, reach = 0.0, spread = 0.0;
  for (uint32_t k = begin; k < end; ++k) {
    const uint32_t t = order_[k];
    const double s = glm::length(glm::dvec3(occluders_[t].center) - center);
    spread = std::max(spread, s);
    radius = std::max(radius, s + occluders_[t].max_radius);
    reach = std::max(reach, s + std::sqrt(static_cast<double>(influence2_[t])));
  }
  const double open = angle_ > 0.0 ? radius / angle_ : std::numeric_limits<double>::infinity();
  node.open2 = static_cast<float>(std::min<double>(open * open, std::numeric_limits<float>::max()));
  node.spread = static_cast<float>(spread) * (1.0f + 1e-6f);
  node.reach2 =
      static_cast<float>(std::min<double>(reach * reach, std::numeric_limits<float>::max()));
  if (end - begin > kLeafTrees) {
    // Median split of the centres along their longest extent.
    const glm::dvec3 extent = hi - lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) {
                       return occluders_[a].center[axis] < occluders_[b].center[axis] ||
                              (occluders_[a].center[axis] == occluders_[b].center[axis] && a < b);
                     });
    build_node(begin, mid);
    node.right = build_node(mid, end);
  }
  nodes_[index] = node;
  return index;
}

float FarField::visibility(const glm::vec3& x, const glm::vec3& n, int skip, bool horizon) const {
  const uint32_t skip_at =
      skip >= 0 ? position_[static_cast<size_t>(skip)] : std::numeric_limits<uint32_t>::max();
  float v = 1.0f, a = 0.0f;
  walk(
      x,
      // The pixel's own tree is never aggregated (a node of one tree is that tree: eq. 8 itself).
      [&](const Node& node, float) { return !(skip_at >= node.begin && skip_at < node.end); },
      [&](const Node& node, const glm::vec3& q, float d2, uint32_t) {
        a += aggregate_occlusion(node.silhouette, node.normal_map, q, d2, n, horizon);
      },
      [&](uint32_t t, uint32_t k, const glm::vec3&, float) {
        if (k != skip_at) v *= hegeman::large_occluder_visibility(x, n, occluders_[t], horizon);
      });
  return v * std::exp(-a);
}

float aggregate_visibility(const std::vector<hegeman::UnitMap>& maps, const glm::vec3& x,
                           const glm::vec3& n, bool horizon) {
  FarField f;
  f.build(maps, 0.0, std::numeric_limits<double>::infinity());
  return f.visibility(x, n, -1, horizon);
}

}  // namespace aoeval
