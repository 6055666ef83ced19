// What every Hegeman et al. 2006 tree estimator (tree-sphere/-ellipsoid/-shells, tree-volume)
// shares besides a tree's own term: the per-object rule (tree, grass, ground, solid), eq. 7-8 for
// the trees as large occluders of everything else, eq. 9 for grass, and the parameters that control
// them (declared here once, listed by each estimator). The estimator supplies only its self term,
// V_self(tree, x, n), for pixels of a tree's own leaves.
//
//   tree    self term of its own tree, times eq. 7-8 for every other tree;
//   ground, solid
//           eq. 7-8 for every tree, multiplied (independent occluders); a ground pixel inside a
//           grass field's footprint and below its blade tips is a grass pixel at its height
//           (parameter grass_ground); a field standing "on" a terrain measures that height from
//           the terrain under the pixel;
//   grass   eq. 9 (see hegeman_model.h), times eq. 7-8 for the trees.
#pragma once

#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/tree_proxies/far_cache.h"
#include "estimators/tree_proxies/hegeman_model.h"
#include "estimators/tree_proxies/occluder_index.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "scenes/surface_height.h"

namespace aoeval {

struct TreeSceneOptions {
  ProxyOptions proxy;
  bool prefer_scene;  // proxy_source = auto
  bool horizon;       // ground_horizon
  bool grass_ground;
  double blade_height;
  double cull = kExactCull;  // cull_occlusion: see occluder_index.h
  double far_angle = 0.0;    // far_field_angle (far_field.h): 0 = the grid, tree by tree; the
                             // parameter's default is tree_scene_params()'s
  double far_cell = 0.0;     // far_grid_cell (far_grid.h): 0 = no grid
  double far_near = 0.0;     // far_near_radius
};

// proxy_source, ground_horizon, grass_ground, blade_height, cull_occlusion, far_field_angle,
// far_grid_cell, far_near_radius: declared once for every tree estimator.
std::vector<ParamSpec> tree_scene_params();
// Reads those eight; `proxy` says which envelope the estimator wants.
TreeSceneOptions tree_scene_options(const ParamSet& p, const ProxyOptions& proxy);

class TreeScene {
 public:
  // Derives (or takes from the scene) one envelope per tree; returns them in the order the
  // self term is indexed by (tree index = position in the returned vector).
  const std::vector<TreeEnvelope>& prepare(const Scene& scene, const TreeSceneOptions& options);
  const std::vector<TreeEnvelope>& envelopes() const { return envelopes_; }
  // {"proxies": [envelope_to_json ...]}: what the harness records beside each result.
  const nlohmann::json& derived() const { return derived_; }

  // The ambient visibility of pixel (x, n) of object `object_id` (the G-buffer's float id).
  // `self(tree, x, n)` is the estimator's term for a pixel of tree `tree`'s own leaves.
  template <class Self>
  float shade(const glm::vec3& x, const glm::vec3& n, float object_id, const Self& self) const {
    const auto id = static_cast<int>(object_id);
    if (id < 0 || static_cast<size_t>(id) >= rules_.size()) return 1.0f;
    const ObjectRule& rule = rules_[static_cast<size_t>(id)];
    switch (rule.rule) {
      case Rule::tree: {
        const float v = self(static_cast<size_t>(rule.index), x, n);
        return outer_.size() > 1 ? v * others(x, n, rule.index) : v;
      }
      case Rule::grass: {
        const GrassField& f = fields_[static_cast<size_t>(rule.index)];
        return grass(f, x.y - root(f, x), n) * others(x, n, -1);
      }
      case Rule::ground:
        if (options_.grass_ground)
          for (const GrassField& f : fields_)
            if (x.x >= f.x0 && x.x <= f.x1 && x.z >= f.z0 && x.z <= f.z1) {
              const float r = root(f, x);
              if (x.y <= r + f.height) return grass(f, x.y - r, n) * others(x, n, -1);
            }
        return others(x, n, -1);
      case Rule::solid:
        return others(x, n, -1);
    }
    return 1.0f;
  }

  // Eq. 7-8 for every tree but `skip` within its radius of influence (options.cull, found
  // through index_), as independent occluders, multiplied in tree order; with far_field_angle > 0
  // distant groups of trees as one aggregate each (far_field.h), precomputed on a grid and
  // interpolated where far_grid_cell > 0 (far_grid.h).
  float others(const glm::vec3& x, const glm::vec3& n, int skip) const {
    if (options_.far_angle > 0.0)
      return far_fields_->grid.covers(x)
                 ? far_fields_->grid.visibility(x, n, skip)
                 : far_fields_->far.visibility(x, n, skip, options_.horizon);
    float v = 1.0f;
    index_.visit(x, [&](uint32_t t) {
      if (static_cast<int>(t) != skip)
        v *= hegeman::large_occluder_visibility(x, n, outer_[t], options_.horizon);
    });
    return v;
  }

 private:
  struct GrassField {
    float base = 0.0f, height = 1.0f;                  // lowest vertex, blade height (eq. 9's h)
    float x0 = 0.0f, x1 = 0.0f, z0 = 0.0f, z1 = 0.0f;  // footprint
    // A field standing "on" a terrain (scenes/stand_on.h): its blades' roots are at the terrain's
    // height under the pixel, not at `base`.
    std::shared_ptr<const SurfaceHeight> ground;
  };
  enum class Rule : uint8_t { solid, ground, tree, grass };
  struct ObjectRule {
    Rule rule = Rule::solid;
    int index = -1;  // into outer_ (trees) or fields_
  };

  // The height of the blade roots under x: the field's base, or its terrain's height there.
  static float root(const GrassField& f, const glm::vec3& x) {
    if (!f.ground) return f.base;
    const auto p = f.ground->at(x.x, x.z);
    return p ? p->y : f.base;
  }
  // Eq. 9 at height pz over the roots, cos theta = n . +Y.
  static float grass(const GrassField& f, float pz, const glm::vec3& n) {
    return hegeman::grass_visibility(pz, f.height, n.y);
  }

  TreeSceneOptions options_{};
  std::vector<TreeEnvelope> envelopes_;
  nlohmann::json derived_ = nlohmann::json::object();
  std::vector<ObjectRule> rules_;
  std::vector<hegeman::UnitMap> outer_;  // per tree: the large occluder of eq. 7-8
  OccluderIndex index_;                  // over outer_ (far_field_angle = 0)
  // over outer_ (far_field_angle > 0), its far part precomputed (far_grid_cell > 0); shared with
  // every other prepare of the same trees (far_cache.h)
  std::shared_ptr<const FarFields> far_fields_;
  std::vector<GrassField> fields_;
};

}  // namespace aoeval
