#include "estimators/tree_volume/tree_volume.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "estimators/tree_proxies/tree_proxy.h"
#include "estimators/tree_proxies/tree_scene.h"
#include "estimators/tree_volume/volume_model.h"

namespace aoeval {

namespace {

namespace hm = hegeman;
namespace vm = volume;

// Filled from the ParamSet (the table below declares the defaults once).
struct Settings {
  ProxyKind kind;
  bool cosine;
  int rings, azimuths;
  double lambda_scale;
  TreeSceneOptions scene;
};

struct Shape {
  hm::UnitMap map;  // the shape as {c + A u : |u| <= 1}: a sphere is A = R I
  float lambda = 0.0f;
};

class TreeVolumeEstimator : public Estimator {
 public:
  explicit TreeVolumeEstimator(const Settings& s)
      : s_(s), dirs_(vm::direction_set(s.rings, s.azimuths, s.cosine)) {}

  void prepare(const EstimateContext& context) override {
    trees_.clear();
    for (const TreeEnvelope& e : scene_.prepare(context.scene, s_.scene)) {
      std::vector<Shape> shapes;
      for (size_t k = 0; k < e.proxy.shapes.size(); ++k)
        shapes.push_back({hm::make_unit_map(e.proxy.shapes[k]),
                          static_cast<float>(e.lambda[k] * s_.lambda_scale)});
      trees_.push_back(std::move(shapes));
    }
    prepared_ = true;
  }

  nlohmann::json derived() const override { return scene_.derived(); }

  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    const GBuffer& g = context.gbuffer;
    EstimateResult r;
    r.ao.assign(g.pixel_count(), 1.0f);
    const auto self_term = [this](size_t tree, const glm::vec3& x, const glm::vec3& n) {
      return self(trees_[tree], x, n);
    };
    tbb::parallel_for(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (size_t k = g.index(0, j), end = k + static_cast<size_t>(g.width); k < end; ++k)
              if (g.covered(k))
                r.ao[k] = scene_.shade(g.position[k], g.normal[k], g.object_id[k], self_term);
        });
    return r;
  }

 private:
  // Int exp(-optical depth) over the fixed direction set, rotated into n's frame.
  float self(const std::vector<Shape>& shapes, const glm::vec3& x, const glm::vec3& n) const {
    const glm::mat3 f = vm::frame(n);
    float v = 0.0f;
    if (shapes.size() == 1) {
      // One convex shape: every direction in its unit space, where the local frame maps to M.
      const Shape& s = shapes.front();
      const glm::vec3 u = s.map.to_unit * (x - s.map.center);
      const glm::mat3 m = s.map.to_unit * f;
      for (size_t d = 0; d < dirs_.dirs.size(); ++d) {
        const float chord = vm::unit_sphere_interval(u, m * dirs_.dirs[d]).length();
        v += dirs_.weights[d] * std::exp(-s.lambda * chord);
      }
      return v;
    }
    // Shells: each shell's interval clipped to its cell (closer to its centre than any other's).
    for (size_t d = 0; d < dirs_.dirs.size(); ++d) {
      const glm::vec3 w = f * dirs_.dirs[d];
      float depth = 0.0f;
      for (size_t k = 0; k < shapes.size(); ++k) {
        const hm::UnitMap& mk = shapes[k].map;
        vm::Interval in = vm::unit_sphere_interval(mk.to_unit * (x - mk.center), mk.to_unit * w);
        for (size_t j = 0; j < shapes.size() && in.t1 > in.t0; ++j) {
          if (j == k) continue;
          // |p - c_k| <= |p - c_j|  <=>  e.(p - m) <= 0, e = c_j - c_k, m their midpoint.
          const glm::vec3 e = shapes[j].map.center - mk.center;
          const float h = glm::dot(e, 0.5f * (shapes[j].map.center + mk.center) - x);
          const float we = glm::dot(w, e);
          if (we > 0.0f)
            in.t1 = std::min(in.t1, h / we);
          else if (we < 0.0f)
            in.t0 = std::max(in.t0, h / we);
          else if (h < 0.0f)
            in.t1 = in.t0;
        }
        depth += shapes[k].lambda * in.length();
      }
      v += dirs_.weights[d] * std::exp(-depth);
    }
    return v;
  }

  Settings s_;
  vm::DirectionSet dirs_;
  bool prepared_ = false;
  TreeScene scene_;
  std::vector<std::vector<Shape>> trees_;  // per tree (TreeScene's order)
};

}  // namespace

EstimatorInfo tree_volume_estimator() {
  EstimatorInfo info;
  info.name = "tree-volume";
  info.summary =
      "trees: hemisphere average of exp(-lambda chord) through the envelope (per-direction "
      "Poisson); ground eq. 7-8; grass eq. 9";
  info.paper =
      "beyond Hegeman, Premoze, Ashikhmin, Drettakis 2006, Approximate Ambient Occlusion for "
      "Trees (I3D '06): §3's Poisson argument applied per direction (eq. 3 with exp(-lambda "
      "chord)) instead of eq. 4-6's cap; eq. 7-8 (ground), eq. 9 (grass), §5 shells";
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::tree_proxies};
  info.params = {
      choice_param({.name = "proxy",
                    .def = "sphere",
                    .choices = {"sphere", "ellipsoid", "shells"},
                    .meaning = "the envelope the chords cross: §3 bounding sphere, §3 ellipsoid "
                               "(Fig. 8), §5 k-means "
                               "shells (closest centre along the ray)"}),
      int_param(
          {.name = "shells",
           .def = 4,
           .min = 1,
           .max = 64,
           .spacing = Spacing::linear,
           .unit = "shells",
           .meaning = "number of k-means shells per derived envelope (§5; proxy = shells only)"}),
      choice_param(
          {.name = "weighting",
           .def = "uniform",
           .choices = {"uniform", "cosine"},
           .meaning =
               "hemisphere weight of exp(-lambda chord): uniform (eq. 3's ambient visibility) "
               "or cosine"}),
      int_param({.name = "rings",
                 .def = 4,
                 .min = 1,
                 .max = 32,
                 .spacing = Spacing::linear,
                 .unit = "directions",
                 .meaning = "Gauss-Legendre nodes in cos(theta) of the fixed direction set (exact "
                            "to degree 2 rings "
                            "- 1 in cos(theta))"}),
      int_param(
          {.name = "azimuths",
           .def = 8,
           .min = 1,
           .max = 64,
           .spacing = Spacing::linear,
           .unit = "directions",
           .meaning =
               "azimuths per ring of the fixed direction set (trapezoid rule; rings x azimuths "
               "directions in all)"}),
      real_param({.name = "lambda_scale",
                  .def = 1.0,
                  .min = 0.01,
                  .max = 100.0,
                  .spacing = Spacing::log,
                  .unit = "",
                  .meaning = "multiplies the derived lambda (§3: G A_leaf / V leaves met per unit "
                             "length, G = 1/2)"}),
  };
  for (ParamSpec& p : tree_scene_params()) info.params.push_back(std::move(p));
  info.definition_doc =
      "unbounded, with the weighting of the `weighting` parameter (uniform: eq. 3's ambient "
      "visibility); §3's Poisson argument has no distance limit";
  info.definition = [](const ParamSet& p) {
    AoDefinition d;
    d.weighting = p.choice("weighting") == "cosine" ? Weighting::cosine : Weighting::uniform;
    return d;
  };
  info.create = [](const ParamSet& p) {
    Settings s{};
    const std::string proxy = p.choice("proxy");
    ProxyOptions options;
    options.kind = proxy == "ellipsoid" ? ProxyKind::ellipsoid
                   : proxy == "shells"  ? ProxyKind::shells
                                        : ProxyKind::sphere;
    options.shells = static_cast<int>(p.integer("shells"));
    s.kind = options.kind;
    s.cosine = p.choice("weighting") == "cosine";
    s.rings = static_cast<int>(p.integer("rings"));
    s.azimuths = static_cast<int>(p.integer("azimuths"));
    s.lambda_scale = p.real("lambda_scale");
    s.scene = tree_scene_options(p, options);
    return std::make_unique<TreeVolumeEstimator>(s);
  };
  return info;
}

}  // namespace aoeval
