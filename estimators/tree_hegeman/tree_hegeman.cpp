#include "estimators/tree_hegeman/tree_hegeman.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

#include "estimators/tree_proxies/hegeman_model.h"
#include "estimators/tree_proxies/tree_proxy.h"

namespace aoeval {

namespace {

namespace hm = hegeman;

struct Shape {
  glm::vec3 center{0.0f};
  float radius = 1.0f;     // sphere and shells
  float alpha_rho = 0.0f;  // eq. 6, per world volume
  hm::UnitMap map;         // ellipsoid
};

struct Tree {
  std::vector<Shape> shapes;  // one, or the shells
  hm::UnitMap outer;          // the large occluder of eq. 7-8
};

struct GrassField {
  float base = 0.0f, height = 1.0f;                  // lowest vertex, blade height (eq. 9's h)
  float x0 = 0.0f, x1 = 0.0f, z0 = 0.0f, z1 = 0.0f;  // footprint
};

enum class Rule : uint8_t { solid, ground, tree, grass };
struct ObjectRule {
  Rule rule = Rule::solid;
  int index = -1;  // into trees_ or fields_
};

// Filled from the ParamSet (the tables below declare the defaults once).
struct Settings {
  ProxyKind kind;
  int shells;  // shells only
  double alpha_rho, alpha_scale, blade_height;
  bool prefer_scene, horizon, grass_ground;
};

class HegemanEstimator : public Estimator {
 public:
  explicit HegemanEstimator(const Settings& s) : s_(s) {}

  void prepare(const EstimateContext& context) override {
    const Scene& scene = context.scene;
    rules_.assign(scene.objects.size(), {});
    trees_.clear();
    fields_.clear();
    ProxyOptions options;
    options.kind = s_.kind;
    options.shells = s_.shells;
    derived_ = {{"proxies", nlohmann::json::array()}};
    for (const TreeEnvelope& e : tree_envelopes(scene, options, s_.prefer_scene)) {
      derived_["proxies"].push_back(envelope_to_json(scene, e));
      Tree t;
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
        t.shapes.push_back(sh);
      }
      const SceneObject& o = scene.objects[e.object];
      if (s_.kind == ProxyKind::shells) {
        ProxyOptions sphere;
        sphere.kind = ProxyKind::sphere;
        t.outer = hm::make_unit_map(derive_proxy(o, sphere).shapes.front());
      } else {
        t.outer = t.shapes.front().map;
      }
      rules_[e.object] = {Rule::tree, static_cast<int>(trees_.size())};
      trees_.push_back(std::move(t));
    }
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      const SceneObject& o = scene.objects[i];
      if (o.role == Role::ground) rules_[i].rule = Rule::ground;
      if (o.role != Role::grass) continue;
      // Eq. 9's h: the blade height. From the world-space mesh (facts.blade_height is in the
      // generator's own space, so it is wrong for a scaled field) unless given as a parameter.
      const Bounds b = o.mesh.bounds();
      GrassField f;
      f.base = b.lower.y;
      f.height = s_.blade_height > 0.0 ? static_cast<float>(s_.blade_height) : b.extent().y;
      if (!(f.height > 0.0f)) f.height = std::numeric_limits<float>::min();
      f.x0 = b.lower.x;
      f.x1 = b.upper.x;
      f.z0 = b.lower.z;
      f.z1 = b.upper.z;
      rules_[i] = {Rule::grass, static_cast<int>(fields_.size())};
      fields_.push_back(f);
    }
    prepared_ = true;
  }

  nlohmann::json derived() const override { return derived_; }

  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    EstimateResult r;
    r.ao.assign(context.gbuffer.pixel_count(), 1.0f);
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
    tbb::parallel_for(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (size_t k = g.index(0, j), end = k + static_cast<size_t>(g.width); k < end; ++k)
              if (g.covered(k)) out[k] = shade<K>(g.position[k], g.normal[k], g.object_id[k]);
        });
  }

  template <ProxyKind K>
  float shade(const glm::vec3& x, const glm::vec3& n, float object_id) const {
    const auto id = static_cast<int>(object_id);
    if (id < 0 || static_cast<size_t>(id) >= rules_.size()) return 1.0f;
    const ObjectRule& rule = rules_[static_cast<size_t>(id)];
    switch (rule.rule) {
      case Rule::tree: {
        const float v = self<K>(trees_[static_cast<size_t>(rule.index)], x, n);
        return trees_.size() > 1 ? v * others(x, n, rule.index) : v;
      }
      case Rule::grass:
        return grass(fields_[static_cast<size_t>(rule.index)], x, n) * others(x, n, -1);
      case Rule::ground:
        if (s_.grass_ground)
          for (const GrassField& f : fields_)
            if (x.x >= f.x0 && x.x <= f.x1 && x.z >= f.z0 && x.z <= f.z1 &&
                x.y <= f.base + f.height)
              return grass(f, x, n) * others(x, n, -1);
        return others(x, n, -1);
      case Rule::solid:
        return others(x, n, -1);
    }
    return 1.0f;
  }

  // Eq. 4-6 with the estimator's envelope.
  template <ProxyKind K>
  static float self(const Tree& t, const glm::vec3& x, const glm::vec3& n) {
    if constexpr (K == ProxyKind::sphere) {
      const Shape& s = t.shapes.front();
      return hm::sphere_visibility(x, n, s.center, s.radius, s.alpha_rho);
    } else if constexpr (K == ProxyKind::ellipsoid) {
      const Shape& s = t.shapes.front();
      return hm::ellipsoid_visibility(x, n, s.map, s.alpha_rho);
    } else {
      // §5: "a point belongs to exactly one such shell (that with the closest center)".
      const Shape* best = &t.shapes.front();
      float best_d = std::numeric_limits<float>::max();
      for (const Shape& s : t.shapes) {
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

  // Eq. 7-8 for every tree but `skip`, as independent occluders.
  float others(const glm::vec3& x, const glm::vec3& n, int skip) const {
    float v = 1.0f;
    for (size_t t = 0; t < trees_.size(); ++t)
      if (static_cast<int>(t) != skip)
        v *= hm::large_occluder_visibility(x, n, trees_[t].outer, s_.horizon);
    return v;
  }

  static float grass(const GrassField& f, const glm::vec3& x, const glm::vec3& n) {
    return hm::grass_visibility(x.y - f.base, f.height, n.y);  // eq. 9, cos theta = n . +Y
  }

  Settings s_;
  bool prepared_ = false;
  nlohmann::json derived_ = nlohmann::json::object();
  std::vector<ObjectRule> rules_;
  std::vector<Tree> trees_;
  std::vector<GrassField> fields_;
};

std::vector<ParamSpec> common_params() {
  return {
      {"alpha_rho",
       ParamType::real,
       0.0,
       0.0,
       1e12,
       false,
       "1/scene units^3",
       "alpha rho of eq. 6 for every tree; 0 = derive 3 lambda / (2 pi R^2) from §3's Poisson "
       "argument (lambda = leaves met per unit length)",
       {}},
      {"alpha_scale",
       ParamType::real,
       1.0,
       0.01,
       100.0,
       true,
       "",
       "multiplies alpha rho: the user-tuned alpha of eq. 6 (§4: chosen by hand per object)",
       {}},
      {"proxy_source",
       ParamType::choice,
       "auto",
       0,
       0,
       false,
       "",
       "auto: the scene file's proxy when it has one of this kind, else derived; derived: always "
       "derive from the leaves (§3 bounding sphere, ellipsoid, §5 k-means shells)",
       {"auto", "derived"}},
      {"ground_horizon",
       ParamType::boolean,
       true,
       0,
       0,
       false,
       "",
       "eq. 7-8: count only the part of a tree's silhouette above the shaded point's tangent plane "
       "(false: eq. 8 verbatim)",
       {}},
      {"grass_ground",
       ParamType::boolean,
       true,
       0,
       0,
       false,
       "",
       "ground pixels inside a grass field's footprint and below its tips use eq. 9 at their "
       "height",
       {}},
      {"blade_height",
       ParamType::real,
       0.0,
       0.0,
       1e6,
       false,
       "scene units",
       "h of eq. 9; 0 = each grass object's height (its world-space vertical extent)",
       {}},
  };
}

EstimatorInfo hegeman_info(ProxyKind kind) {
  EstimatorInfo info;
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::tree_proxies};
  info.params = common_params();
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
      info.params.push_back({"shells",
                             ParamType::integer,
                             4,
                             1,
                             64,
                             false,
                             "shells",
                             "number of k-means shells per derived tree envelope (§5)",
                             {}});
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
    if (kind == ProxyKind::shells) s.shells = static_cast<int>(p.integer("shells"));
    s.alpha_rho = p.real("alpha_rho");
    s.alpha_scale = p.real("alpha_scale");
    s.prefer_scene = p.choice("proxy_source") == "auto";
    s.horizon = p.boolean("ground_horizon");
    s.grass_ground = p.boolean("grass_ground");
    s.blade_height = p.real("blade_height");
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
