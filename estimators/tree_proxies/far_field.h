// A far-field term for eq. 7-8 over a forest (issue 45): a bounding-sphere hierarchy over the
// trees' large occluders whose nodes carry an aggregate occluder, so that a pixel evaluates a
// distant group of trees as one (Barnes-Hut's opening rule; hierarchical radiosity's clusters).
//
// How trees combine. TreeScene multiplies eq. 8's factors of every tree (independent occluders;
// Hegeman et al. give no rule for several trees, eq. 8 is per occluder): V = prod_t (1 - a_t), with
// a_t = A_SA,t h_t / (2 pi) (eq. 7 times the above-horizon fraction). A node N far from the pixel
// replaces the product over its trees by
//
//   exp(-a_N),   a_N = pi |B_N q^| / d^2 * h_N / (2 pi),   q = c_N - x, d = |q|, q^ = q / d,
//
// where B_N = sum_t |det A_t| A_t^-1 (eq. 7's silhouette pi |det A| |A^-1 w| is pi |B_t w|, so a
// node of spheres has pi |B_N q^| = pi sum_t r_t^2 exactly), c_N the centre of the trees weighted
// by w_t = trace(B_t) / 3 (r_t^2 for a sphere: the first-order term of the expansion of
// sum_t w_t / |c_t - x|^2 about c_N then vanishes), and h_N the above-horizon fraction of one
// representative tree at c_N (silhouette radius |G_N n|, G_N = sum_t w_t A_t^T / sum_t w_t).
//
// Error for a node of spheres (h = 1), rho = max_t |c_t - c_N|, theta = rho / d: Taylor's theorem
// with the Hessian of 1/|y|^2 (norm <= 6 / |y|^4) gives
//   |sum_t a_t - a_N| <= 3 theta^2 / (1 - theta)^4 * a_N
// and -a - a^2 / (2 (1 - a)) <= ln(1 - a) <= -a gives
//   0 <= exp(-sum_t a_t) - prod_t (1 - a_t) <= sum_t a_t^2 / (2 (1 - max_t a_t)),
// so the aggregate is within the sum of the two of the exact product (far_field_test.cpp).
//
// Opening rule: a node is aggregated when its bounding sphere (centre c_N, radius R_N enclosing
// every tree's largest semi-axis around its centre) has R_N <= angle * d, i.e. its angular radius
// seen from x is at most `angle` (radians, as a tangent), and it holds more than one tree (a lone
// tree is eq. 8 itself) and not the pixel's own. angle = 0 never aggregates: TreeScene
// then keeps the occluder grid (bit-equal to today's answers).
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "estimators/tree_proxies/hegeman_model.h"

namespace aoeval {

class FarField {
 public:
  // `epsilon` is cull_occlusion (occluder_index.h): a node whose every tree lies beyond its radius
  // of influence r_max / sqrt(2 epsilon) is skipped, as the grid skips such a tree; 0 skips none.
  void build(const std::vector<hegeman::UnitMap>& occluders, double epsilon, double angle);

  // Eq. 7-8 for every tree but `skip`: near trees one by one (the product), far nodes aggregated.
  float visibility(const glm::vec3& x, const glm::vec3& n, int skip, bool horizon) const;

  size_t nodes() const { return nodes_.size(); }

  // What the precomputed far field (far_grid.h) sums from x: every tree within its radius of
  // influence as f(q, d2, a, false, t), except that a node of more than one tree whose trees all
  // lie farther than `near` from x and which the opening rule aggregates is f(q, d2, a_N, true,
  // node). q = centre - x, a = |B q| / (2 d^3): eq. 7-8's occlusion before the horizon fraction.
  template <class F>
  void gather(const glm::vec3& x, float near, F&& f) const {
    walk(
        x, [&](const Node& node, float d2) { return std::sqrt(d2) - node.spread >= near; },
        [&](const Node& node, const glm::vec3& q, float d2, uint32_t index) {
          f(q, d2, glm::length(node.silhouette * q) / (2.0f * d2 * std::sqrt(d2)), true, index);
        },
        [&](uint32_t t, uint32_t, const glm::vec3& q, float d2) {
          f(q, d2, glm::length(silhouette_[t] * q) / (2.0f * d2 * std::sqrt(d2)), false, t);
        });
  }
  // G of a tree (gather's `false`) or of a node (`true`): |G n| is the silhouette's radius along n.
  const glm::mat3& normal_map(bool node, uint32_t id) const {
    return node ? nodes_[id].normal_map : normal_map_[id];
  }

 private:
  struct Node {
    glm::vec3 center{0.0f};       // c_N
    float open2 = 0.0f;           // (R_N / angle)^2: aggregated where d^2 >= open2
    float reach2 = 0.0f;          // (max_t |c_t - c_N| + radius of influence_t)^2; skipped beyond
    float spread = 0.0f;          // max_t |c_t - c_N|
    glm::mat3 silhouette{0.0f};   // B_N
    glm::mat3 normal_map{0.0f};   // G_N
    uint32_t begin = 0, end = 0;  // its trees: order_[begin .. end)
    uint32_t right = 0;           // inner: the right child (the left is the next node); 0: a leaf
  };
  uint32_t build_node(uint32_t begin, uint32_t end);

  // The hierarchy's walk from x: a node of more than one tree within reach whose opening rule
  // holds and that aggregate(node, d2) accepts is on_node(node, q, d2, index); every other tree
  // within its radius of influence is on_tree(t, k, q, d2) (k its position in order_).
  template <class A, class N, class T>
  void walk(const glm::vec3& x, A&& aggregate, N&& on_node, T&& on_tree) const {
    if (nodes_.empty()) return;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const uint32_t index = stack[--top];
      const Node& node = nodes_[index];
      const glm::vec3 q = node.center - x;
      const float d2 = glm::dot(q, q);
      if (cull_ && d2 > node.reach2) continue;
      if (d2 >= node.open2 && node.end - node.begin > 1 && aggregate(node, d2)) {
        on_node(node, q, d2, index);
        continue;
      }
      if (node.right == 0) {
        for (uint32_t k = node.begin; k < node.end; ++k) {
          const uint32_t t = order_[k];
          const glm::vec3 qt = occluders_[t].center - x;
          const float dt2 = glm::dot(qt, qt);
          if (dt2 <= influence2_[t]) on_tree(t, k, qt, dt2);
        }
        continue;
      }
      stack[top++] = node.right;
      stack[top++] = index + 1;
    }
  }

  std::vector<hegeman::UnitMap> occluders_;
  std::vector<glm::mat3> silhouette_, normal_map_;  // per tree: B_t, (A_t A_t^T)^(1/2)
  std::vector<float> influence2_;                   // per tree: squared radius of influence
  bool cull_ = false;
  double angle_ = 0.0;
  std::vector<uint32_t> order_, position_;  // order_[position_[t]] = t
  std::vector<Node> nodes_;
};

// The aggregate of `maps` seen from (x, n): exp(-a_N) above, for tests.
float aggregate_visibility(const std::vector<hegeman::UnitMap>& maps, const glm::vec3& x,
                           const glm::vec3& n, bool horizon);

}  // namespace aoeval
