#include "estimators/tree_hegeman/tree_hegeman.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "estimators/tree_proxies/hegeman_model.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "estimators/tree_proxies/tree_scene.h"

namespace aoeval {

namespace {

namespace hm = hegeman;

struct Shape {
  glm::vec3 center{0.0f};
  float radius = 1.0f;     // sphere and shells
  float alpha_rho = 0.0f;  // eq. 6, per world volume
  hm::UnitMap map;         // ellipsoid
};

// Filled from the ParamSet (the tables below declare the defaults once).
struct Settings {
  ProxyKind kind;
  double alpha_rho, alpha_scale;
  bool ambient_only;
  TreeSceneOptions scene;
};

class HegemanEstimator : public Estimator {
 public:
  explicit HegemanEstimator(const Settings& s) : s_(s) {}

  void prepare(const EstimateContext& context) override {
    trees_.clear();
    for (const TreeEnvelope& e : scene_.prepare(context.scene, s_.scene)) {
      std::vector<Shape> shapes;  // one, or the shells
      for (size_t k = 0; k < e.proxy.shapes.size(); ++k) {
        const Ellipsoid& el = e.proxy.shapes[k];
        Shape sh;
        sh.center = el.center;
        sh.radius = el.radii.x;
        sh.map = hm::make_unit_map(el);
        // alpha rho = 3 lambda / (2 pi R^2), R the (volume-equivalent) radius: see the header.
        const double r =
            s_.kind == ProxyKind::ellipsoid ? std::cbrt(double(sh.map.det)) : sh.radius;
        const double derived = 3.0 * e.lambda[k] / (2.0 * double(hm::kPi) * r * r);
        sh.alpha_rho =
            static_cast<float>((s_.alpha_rho > 0.0 ? s_.alpha_rho : derived) * s_.alpha_scale);
        shapes.push_back(sh);
      }
      trees_.push_back(std::move(shapes));
    }
    prepared_ = true;
  }

  nlohmann::json derived() const override { return scene_.derived(); }

  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    EstimateResult r;
    r.ao.assign(context.gbuffer.pixel_count(), 1.0f);
    if (s_.ambient_only) {
      shade_ambient(context.gbuffer, r.ao.data());
      return r;
    }
    switch (s_.kind) {  // one loop per envelope kind, so the per-pixel code has no kind switch
      case ProxyKind::sphere:
        shade_image<ProxyKind::sphere>(context.gbuffer, r.ao.data());
        break;
      case ProxyKind::ellipsoid:
        shade_image<ProxyKind::ellipsoid>(context.gbuffer, r.ao.data());
        break;
      case ProxyKind::shells:
        shade_image<ProxyKind::shells>(context.gbuffer, r.ao.data());
        break;
    }
    return r;
  }

 private:
  template <ProxyKind K>
  void shade_image(const GBuffer& g, float* out) const {
    const auto self_term = [this](size_t tree, const glm::vec3& x, const glm::vec3& n) {
      return self<K>(trees_[tree], x, n);
    };
    tbb::parallel_for(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (size_t k = g.index(0, j), end = k + static_cast<size_t>(g.width); k < end; ++k)
              if (g.covered(k))
                out[k] = scene_.shade(g.position[k], g.normal[k], g.object_id[k], self_term);
        });
  }

  // §4's ambient-only shader: the pass below (the same rows, coverage test and writes, after the
  // same prepare) with the visibility left out, so that its time is the pass's own and what the
  // AO shader adds is eq. 4-6's work.
  void shade_ambient(const GBuffer& g, float* out) const {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (size_t k = g.index(0, j), end = k + static_cast<size_t>(g.width); k < end; ++k)
              if (g.covered(k)) out[k] = 1.0f;
        });
  }

  // Eq. 4-6 with the estimator's envelope.
  template <ProxyKind K>
  static float self(const std::vector<Shape>& shapes, const glm::vec3& x, const glm::vec3& n) {
    if constexpr (K == ProxyKind::sphere) {
      const Shape& s = shapes.front();
      return hm::sphere_visibility(x, n, s.center, s.radius, s.alpha_rho);
    } else if constexpr (K == ProxyKind::ellipsoid) {
      const Shape& s = shapes.front();
      return hm::ellipsoid_visibility(x, n, s.map, s.alpha_rho);
    } else {
      // §5: "a point belongs to exactly one such shell (that with the closest center)".
      const Shape* best = &shapes.front();
      float best_d = std::numeric_limits<float>::max();
      for (const Shape& s : shapes) {
        const glm::vec3 q = x - s.center;
        const float d = glm::dot(q, q);
        if (d < best_d) {
          best_d = d;
          best = &s;
        }
      }
      return hm::sphere_visibility(x, n, best->center, best->radius, best->alpha_rho);
    }
  }

  Settings s_;
  bool prepared_ = false;
  TreeScene scene_;
  std::vector<std::vector<Shape>> trees_;  // per tree (TreeScene's order): its shapes
};

std::vector<ParamSpec> common_params() {
  return {
      real_param({.name = "alpha_rho",
                  .def = 0.0,
                  .min = 0.0,
                  .max = 1e12,
                  .spacing = Spacing::linear,
                  .unit = "1/scene units^3",
                  .meaning = "alpha rho of eq. 6 for every tree; 0 = derive 3 lambda / (2 pi R^2) "
                             "from §3's Poisson "
                             "argument (lambda = leaves met per unit length)"}),
      real_param({.name = "alpha_scale",
                  .def = 1.0,
                  .min = 0.01,
                  .max = 100.0,
                  .spacing = Spacing::log,
                  .unit = "",
                  .meaning = "multiplies alpha rho: the user-tuned alpha of eq. 6 (§4: chosen by "
                             "hand per object)"}),
      bool_param(
          {.name = "ambient_only",
           .def = false,
           .meaning =
               "§4's ambient-only shader (Fig. 12 bottom row): the same per-pixel pass with the "
               "visibility left out, every covered pixel 1; a throughput baseline"}),
  };
}

EstimatorInfo hegeman_info(ProxyKind kind) {
  EstimatorInfo info;
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::tree_proxies};
  info.params = common_params();
  for (ParamSpec& p : tree_scene_params()) info.params.push_back(std::move(p));
  info.paper =
      "Hegeman, Premoze, Ashikhmin, Drettakis 2006, Approximate Ambient Occlusion for Trees "
      "(I3D '06): ";
  switch (kind) {
    case ProxyKind::sphere:
      info.name = "tree-sphere";
      info.summary =
          "trees: exp(-alpha rho f V_cap) of a spherical envelope; ground eq. 7-8; grass "
          "eq. 9";
      info.paper += "eq. 4-6 (sphere), eq. 7-8 (ground), eq. 9 (grass)";
      break;
    case ProxyKind::ellipsoid:
      info.name = "tree-ellipsoid";
      info.summary = "tree-sphere after mapping an ellipsoidal envelope to the unit sphere";
      info.paper +=
          "eq. 4-6 on the ellipsoid mapped to a sphere (§3, Fig. 3 right, Fig. 8), "
          "eq. 7-8, eq. 9";
      break;
    case ProxyKind::shells:
      info.name = "tree-shells";
      info.summary = "tree-sphere with k-means spherical shells, the closest centre per point";
      info.paper +=
          "eq. 4-6 per spherical shell, closest centre (§5, Fig. 3 left), eq. 7-8, "
          "eq. 9";
      info.params.push_back(
          int_param({.name = "shells",
                     .def = 4,
                     .min = 1,
                     .max = 64,
                     .spacing = Spacing::linear,
                     .unit = "shells",
                     .meaning = "number of k-means shells per derived tree envelope (§5)"}));
      break;
  }
  info.definition_doc =
      "uniform-weighted, unbounded: eq. 3's ambient visibility (1/2pi) Int V dw, and §3's "
      "Poisson argument weighs every direction alike with no distance limit";
  info.definition = [](const ParamSet&) {
    AoDefinition d;
    d.weighting = Weighting::uniform;
    return d;
  };
  info.create = [kind](const ParamSet& p) {
    Settings s{};
    s.kind = kind;
    ProxyOptions proxy;
    proxy.kind = kind;
    if (kind == ProxyKind::shells) proxy.shells = static_cast<int>(p.integer("shells"));
    s.alpha_rho = p.real("alpha_rho");
    s.alpha_scale = p.real("alpha_scale");
    s.ambient_only = p.boolean("ambient_only");
    s.scene = tree_scene_options(p, proxy);
    return std::make_unique<HegemanEstimator>(s);
  };
  return info;
}

}  // namespace

EstimatorInfo tree_sphere_estimator() {
  return hegeman_info(ProxyKind::sphere);
}
EstimatorInfo tree_ellipsoid_estimator() {
  return hegeman_info(ProxyKind::ellipsoid);
}
EstimatorInfo tree_shells_estimator() {
  return hegeman_info(ProxyKind::shells);
}

}  // namespace aoeval
