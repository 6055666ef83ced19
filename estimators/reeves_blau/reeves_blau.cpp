#include "estimators/reeves_blau/reeves_blau.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "estimators/tree_proxies/hegeman_model.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "scenes/instances.h"

namespace aoeval {

namespace {

struct Envelope {
  hegeman::UnitMap map;
  float k = 0.0f;       // attenuation per scene unit
  bool sphere = false;  // equal radii: depth = R - |x - c| (the same value, one sqrt fewer)
  float radius = 0.0f;
};

class ReevesBlauEstimator : public Estimator {
 public:
  ReevesBlauEstimator(ProxyKind kind, double attenuation, bool prefer_scene)
      : kind_(kind), attenuation_(attenuation), prefer_scene_(prefer_scene) {}

  void prepare(const EstimateContext& context) override {
    const Scene& scene = context.scene;
    tree_of_.assign(PlacementIds(scene).count, -1);  // by G-buffer id
    envelopes_.clear();
    ProxyOptions options;
    options.kind = kind_;
    derived_ = {{"proxies", nlohmann::json::array()}};
    for (const TreeEnvelope& e : tree_envelopes(scene, options, prefer_scene_)) {
      derived_["proxies"].push_back(envelope_to_json(scene, e));
      Envelope v;
      const Ellipsoid& shape = e.proxy.shapes.front();
      v.map = hegeman::make_unit_map(shape);
      v.sphere = shape.radii.x == shape.radii.y && shape.radii.y == shape.radii.z;
      v.radius = shape.radii.x;
      v.k = static_cast<float>(attenuation_ > 0.0 ? attenuation_ : e.lambda.front());
      tree_of_[e.placement] = static_cast<int>(envelopes_.size());
      envelopes_.push_back(v);
    }
    prepared_ = true;
  }

  nlohmann::json derived() const override { return derived_; }

  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    const GBuffer& g = context.gbuffer;
    EstimateResult r;
    r.ao.assign(g.pixel_count(), 1.0f);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& rows) {
          for (int j = rows.begin(); j < rows.end(); ++j)
            for (int i = 0; i < g.width; ++i) {
              const size_t k = g.index(i, j);
              if (!g.covered(k)) continue;
              const auto id = static_cast<int>(g.object_id[k]);
              if (id < 0 || static_cast<size_t>(id) >= tree_of_.size() ||
                  tree_of_[static_cast<size_t>(id)] < 0)
                continue;
              const Envelope& e =
                  envelopes_[static_cast<size_t>(tree_of_[static_cast<size_t>(id)])];
              const float depth =
                  e.sphere ? std::max(0.0f, e.radius - glm::length(g.position[k] - e.map.center))
                           : hegeman::envelope_depth(g.position[k], e.map);
              r.ao[k] = std::exp(-e.k * depth);
            }
        });
    return r;
  }

 private:
  ProxyKind kind_;
  double attenuation_;
  bool prefer_scene_;
  bool prepared_ = false;
  nlohmann::json derived_ = nlohmann::json::object();
  std::vector<int> tree_of_;  // per scene object: its envelope, or -1
  std::vector<Envelope> envelopes_;
};

}  // namespace

EstimatorInfo reeves_blau_estimator() {
  EstimatorInfo info;
  info.name = "reeves-blau";
  info.summary = "tree pixels: ambient attenuated by exp(-k depth inside the tree's envelope)";
  info.paper =
      "Reeves and Blau 1985, Approximate and probabilistic algorithms for shading and rendering "
      "structured particle systems, as Hegeman et al. 2006 describe it (§2, Fig. 4 and 12)";
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::tree_proxies};
  info.params = {
      real_param({.name = "attenuation",
                  .def = 0.0,
                  .min = 0.0,
                  .max = 1e6,
                  .spacing = Spacing::linear,
                  .unit = "1/scene units",
                  .meaning =
                      "k of V = exp(-k depth); 0 = lambda, the leaves a ray meets per unit length "
                      "(Hegeman et al. "
                      "§3)"}),
      choice_param(
          {.name = "envelope",
           .def = "sphere",
           .choices = {"sphere", "ellipsoid"},
           .meaning =
               "the tree envelope the depth is measured in: the bounding sphere or the moment "
               "ellipsoid"}),
      choice_param({.name = "proxy_source",
                    .def = "auto",
                    .choices = {"auto", "derived"},
                    .meaning =
                        "auto: the scene file's proxy when it has one of this kind, else derived; "
                        "derived: always "
                        "derive from the leaves"}),
  };
  info.definition_doc =
      "uniform-weighted, unbounded: compared against Hegeman et al.'s eq. 3 ambient visibility";
  info.definition = [](const ParamSet&) {
    AoDefinition d;
    d.weighting = Weighting::uniform;
    return d;
  };
  info.create = [](const ParamSet& p) {
    const ProxyKind kind =
        p.choice("envelope") == "ellipsoid" ? ProxyKind::ellipsoid : ProxyKind::sphere;
    return std::make_unique<ReevesBlauEstimator>(kind, p.real("attenuation"),
                                                 p.choice("proxy_source") == "auto");
  };
  return info;
}

}  // namespace aoeval
