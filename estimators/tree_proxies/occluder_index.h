// A spatial index over the trees' large occluders (eq. 7-8), so that a pixel visits only the
// trees within their radius of influence instead of every tree of a forest (issue 45).
//
// Eq. 7-8's occlusion of an ellipsoid with semi-axes r1 >= r2 >= r3 at distance d from its centre
// is A_SA / 2pi = |det A| |A^-1 q| / (2 d^3) (times the horizon fraction <= 1) <= r1 r2 / (2 d^2)
// <= r1^2 / (2 d^2), so a tree occludes a pixel by at most `epsilon` beyond its radius of influence
//
//   R = r1 / sqrt(2 epsilon).
//
// The index is a uniform grid over the x-z footprint of the centres (forests stand on terrain);
// `visit` calls f(t) for every tree whose centre lies within R of the point, in increasing t,
// so a product over the visited trees multiplies in the same order as a loop over every tree.
// With epsilon = kExactCull = 2^-26 every skipped factor 1 - A_SA / 2pi rounds to 1.0f (its
// occlusion is below half an ulp of 1, 2^-25, with a factor 2 to spare for rounding), so the
// product is bit-equal to the loop over every tree; a larger epsilon trades at most the sum of
// the skipped occlusions per pixel for time. epsilon = 0 visits every tree.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "estimators/tree_proxies/hegeman_model.h"

namespace aoeval {

inline constexpr double kExactCull = 1.0 / 67108864.0;  // 2^-26

class OccluderIndex {
 public:
  void build(const std::vector<hegeman::UnitMap>& occluders, double epsilon);

  // f(t) for every occluder t whose centre is within its radius of influence of x (and every t
  // when the index covers everything from anywhere), in increasing t.
  template <class F>
  void visit(const glm::vec3& x, F&& f) const {
    if (all_) {
      for (uint32_t t = 0; t < radius2_.size(); ++t) f(t);
      return;
    }
    const int i0 = cell_of(x.x - reach_, x0_, nx_), i1 = cell_of(x.x + reach_, x0_, nx_);
    const int j0 = cell_of(x.z - reach_, z0_, nz_), j1 = cell_of(x.z + reach_, z0_, nz_);
    thread_local std::vector<uint32_t> near;
    near.clear();
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const size_t c = static_cast<size_t>(j) * static_cast<size_t>(nx_) + static_cast<size_t>(i);
        for (uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
          const uint32_t t = items_[k];
          const glm::vec3 q = centers_[t] - x;
          if (q.x * q.x + q.y * q.y + q.z * q.z <= radius2_[t]) near.push_back(t);
        }
      }
    std::sort(near.begin(), near.end());
    for (const uint32_t t : near) f(t);
  }

  bool covers_all() const { return all_; }
  size_t cells() const { return start_.empty() ? 0 : start_.size() - 1; }

 private:
  int cell_of(float v, float origin, int n) const {
    const float c = std::floor((v - origin) / cell_);
    return !(c >= 0.0f) ? 0 : (c >= static_cast<float>(n) ? n - 1 : static_cast<int>(c));
  }

  bool all_ = true;
  float reach_ = 0.0f;  // the largest radius of influence
  float cell_ = 1.0f;   // cell side
  float x0_ = 0.0f, z0_ = 0.0f;
  int nx_ = 1, nz_ = 1;
  std::vector<glm::vec3> centers_;
  std::vector<float> radius2_;   // squared radius of influence per occluder
  std::vector<uint32_t> start_;  // cell c holds items_[start_[c] .. start_[c + 1])
  std::vector<uint32_t> items_;  // occluder indices, increasing within a cell
};

}  // namespace aoeval
