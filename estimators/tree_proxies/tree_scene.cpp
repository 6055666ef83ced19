#include "estimators/tree_proxies/tree_scene.h"

#include <algorithm>
#include <map>

#include "base/errors.h"
#include "scenes/instances.h"
#include "scenes/stand_on.h"

namespace aoeval {

std::vector<ParamSpec> tree_scene_params() {
  return {
      choice_param(
          {.name = "proxy_source",
           .def = "auto",
           .choices = {"auto", "derived"},
           .meaning = "auto: the scene file's proxy when it has one of this kind, else derived; "
                      "derived: always "
                      "derive from the leaves (§3 bounding sphere, ellipsoid, §5 k-means shells)"}),
      bool_param(
          {.name = "ground_horizon",
           .def = true,
           .meaning =
               "eq. 7-8: count only the part of a tree's silhouette above the shaded point's "
               "tangent plane "
               "(false: eq. 8 verbatim)"}),
      bool_param({.name = "grass_ground",
                  .def = true,
                  .meaning = "ground pixels inside a grass field's footprint and below its tips "
                             "use eq. 9 at their "
                             "height"}),
      real_param(
          {.name = "blade_height",
           .def = 0.0,
           .min = 0.0,
           .max = 1e6,
           .spacing = Spacing::linear,
           .unit = "scene units",
           .meaning =
               "h of eq. 9; 0 = each grass object's height (its world-space vertical extent)"}),
      real_param(
          {.name = "cull_occlusion",
           .def = kExactCull,
           .min = 0.0,
           .max = 0.25,
           .spacing = Spacing::linear,
           .unit = "",
           .meaning =
               "eq. 7-8: a tree is skipped where its occlusion is at most this by the bound "
               "r_max^2 / (2 d^2), i.e. beyond r_max / sqrt(2 cull_occlusion) of its centre, "
               "found through a grid over the trees; the default 2^-26 skips only factors that "
               "round to 1.0f (bit-equal to every tree), larger values change a pixel by at most "
               "the sum of its skipped occlusions; 0 visits every tree"}),
      real_param(
          {.name = "far_field_angle",
           .def = 0.7,
           .min = 0.0,
           .max = 0.9,
           .spacing = Spacing::linear,
           .unit = "radians",
           .meaning =
               "eq. 7-8's far field: a group of trees (a node of a hierarchy over them) whose "
               "bounding sphere's angular radius from the pixel (radius / distance) is at most "
               "this is one aggregate occluder (the trees' summed silhouettes at their centroid, "
               "exp(-occlusion) in place of the product of their factors); 0 = every tree on its "
               "own (the grid; bit-equal to the loop over every tree at the default cull)"}),
      real_param(
          {.name = "far_grid_cell",
           .def = 4.0,
           .min = 0.0,
           .max = 1e6,
           .spacing = Spacing::linear,
           .unit = "scene units",
           .meaning =
               "with far_field_angle > 0: the side of the cells of a grid over the trees at "
               "whose nodes the far trees' occlusion (beyond far_near_radius, far_grid.h) is "
               "summed once per scene for 26 normal directions and interpolated per pixel; 0 = "
               "no grid (the far field per pixel, as in scenes of fewer than 100 trees)"}),
      real_param(
          {.name = "far_near_radius",
           .def = 2.0,
           .min = 0.0,
           .max = 1e6,
           .spacing = Spacing::linear,
           .unit = "scene units",
           .meaning =
               "with the far-field grid: R, the near radius; a tree is evaluated exactly per "
               "pixel within max(R/2, its largest semi-axis) of its centre, blended by a "
               "smoothstep over the next R/2, and comes from the grid beyond (far_grid.h)"}),
  };
}

TreeSceneOptions tree_scene_options(const ParamSet& p, const ProxyOptions& proxy) {
  TreeSceneOptions o;
  o.proxy = proxy;
  o.prefer_scene = p.choice("proxy_source") == "auto";
  o.horizon = p.boolean("ground_horizon");
  o.grass_ground = p.boolean("grass_ground");
  o.blade_height = p.real("blade_height");
  o.cull = p.real("cull_occlusion");
  o.far_angle = p.real("far_field_angle");
  o.far_cell = p.real("far_grid_cell");
  o.far_near = p.real("far_near_radius");
  return o;
}

namespace {

// What the row records of the proxies: a plain tree's envelope as used (world space); an
// instanced object's once, as its prototype's (object space) with its instance count, since
// every copy is that envelope placed by the instance's transform (tree_envelopes). One entry per
// placed tree made forest-10k's row 3 MB of JSON, rebuilt every frame.
nlohmann::json proxies_record(const Scene& scene, const std::vector<TreeEnvelope>& placed,
                              const std::vector<TreeEnvelope>& prototypes) {
  nlohmann::json out = nlohmann::json::array();
  std::map<size_t, const TreeEnvelope*> prototype_of;  // by object index
  for (const TreeEnvelope& p : prototypes) prototype_of[p.object] = &p;
  for (const TreeEnvelope& e : placed) {
    const SceneObject& o = scene.objects[e.object];
    if (o.instances.empty()) {
      out.push_back(envelope_to_json(scene, e));
      continue;
    }
    const auto it = prototype_of.find(e.object);
    if (it == prototype_of.end()) continue;  // recorded at the object's first copy
    nlohmann::json j = envelope_to_json(scene, *it->second);
    j["object"] = o.name;
    j["instances"] = o.instances.size();
    j["space"] = "object";
    out.push_back(std::move(j));
    prototype_of.erase(it);
  }
  return out;
}

}  // namespace

const std::vector<TreeEnvelope>& TreeScene::prepare(const Scene& scene,
                                                    const TreeSceneOptions& options) {
  options_ = options;
  const PlacementIds ids(scene);
  rules_.assign(ids.count, {});
  outer_.clear();
  fields_.clear();
  derived_ = {{"proxies", nlohmann::json::array()}};
  std::map<size_t, TreeProxy> bounding;  // shells: each tree object's leaf bounding sphere
  std::vector<TreeEnvelope> prototypes;
  envelopes_ = tree_envelopes(scene, options.proxy, options.prefer_scene, &prototypes);
  derived_["proxies"] = proxies_record(scene, envelopes_, prototypes);
  for (const TreeEnvelope& e : envelopes_) {
    // Eq. 7-8's occluder is one convex shape: the envelope itself, or for shells (which overlap
    // and so cannot be added) the bounding sphere of the leaves.
    if (options.proxy.kind == ProxyKind::shells) {
      ProxyOptions sphere;
      sphere.kind = ProxyKind::sphere;
      // Derived once per object (from the prototype when instanced), placed per instance.
      if (bounding.count(e.object) == 0)
        bounding[e.object] = derive_proxy(scene.objects[e.object], sphere);
      TreeProxy outer = bounding[e.object];
      const SceneObject& o = scene.objects[e.object];
      if (!o.instances.empty()) place_proxy(o.instances[e.placement - ids.first[e.object]], outer);
      outer_.push_back(hegeman::make_unit_map(outer.shapes.front()));
    } else {
      outer_.push_back(hegeman::make_unit_map(e.proxy.shapes.front()));
    }
    rules_[e.placement] = {Rule::tree, static_cast<int>(outer_.size() - 1)};
  }
  if (options.far_angle > 0.0) {
    far_fields_ = shared_far_fields({.occluders = outer_,
                                     .region = scene.bounds(),
                                     .cull = options.cull,
                                     .angle = options.far_angle,
                                     .cell = options.far_cell,
                                     .near = options.far_near,
                                     .horizon = options.horizon});
  } else {
    index_.build(outer_, options.cull);
  }
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const size_t placements = std::max<size_t>(1, o.instances.size());
    if (o.role == Role::ground)
      for (size_t k = 0; k < placements; ++k) rules_[ids.first[i] + k].rule = Rule::ground;
    if (o.role != Role::grass) continue;
    // An instanced field would need a footprint per copy; one clear refusal instead.
    if (!o.instances.empty())
      throw InputError("scene '" + scene.name + "': grass object '" + o.name +
                       "' is instanced; the tree estimators' eq. 9 takes one field per object");
    // Eq. 9's h: the blade height. From the world-space mesh (facts.blade_height is in the
    // generator's own space, so it is wrong for a scaled field) unless given as a parameter.
    const Bounds b = o.mesh.bounds();
    GrassField f;
    f.base = b.lower.y;
    f.height = b.extent().y;
    if (!o.on.empty()) {  // on a terrain: heights from the ground under the pixel and the root
      const auto g = std::find_if(scene.objects.begin(), scene.objects.end(),
                                  [&](const SceneObject& s) { return s.name == o.on; });
      if (g != scene.objects.end())
        f.ground = std::make_shared<SurfaceHeight>(
            g->mesh, SurfaceHeight::Footprint{b.lower.x, b.upper.x, b.lower.z, b.upper.z});
      if (const auto h = grass_blade_height(o)) f.height = *h;
    }
    if (options.blade_height > 0.0) f.height = static_cast<float>(options.blade_height);
    if (!(f.height > 0.0f)) f.height = std::numeric_limits<float>::min();
    f.x0 = b.lower.x;
    f.x1 = b.upper.x;
    f.z0 = b.lower.z;
    f.z1 = b.upper.z;
    rules_[ids.first[i]] = {Rule::grass, static_cast<int>(fields_.size())};
    fields_.push_back(f);
  }
  return envelopes_;
}

}  // namespace aoeval
