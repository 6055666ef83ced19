#include "estimators/raytraced/raytraced.h"

#include "estimators/power_falloff_param.h"
#include "estimators/seed_param.h"
#include "sampling/ao_tracer.h"

namespace aoeval {

namespace {

AoDefinition definition_of(const ParamSet& p) {
  AoDefinition d;
  d.weighting = parse_weighting(p.choice("weighting"), "weighting");
  const double dmax = p.real("dmax");
  d.dmax = dmax > 0.0 ? dmax : std::numeric_limits<double>::infinity();
  d.falloff = falloff_of(p);
  validate_definition(d);
  return d;
}

class RaytracedEstimator : public Estimator {
 public:
  explicit RaytracedEstimator(const ParamSet& p) {
    settings_.spp = static_cast<int>(p.integer("rays"));
    settings_.definition = definition_of(p);
    settings_.sampler = parse_sampler(p.choice("sampler"));
    settings_.seed = static_cast<uint64_t>(p.integer("seed"));
  }
  EstimateResult run(const EstimateContext& context) override {
    TracedAo image = trace_ao(context.embree, context.gbuffer, settings_);
    EstimateResult r;
    r.ao = std::move(image.ao);
    r.extra_channels["AO_stderr"] = std::move(image.stderr_ao);
    return r;
  }

 private:
  AoTraceSettings settings_;
};

}  // namespace

EstimatorInfo raytraced_estimator() {
  EstimatorInfo info;
  info.name = "raytraced";
  info.summary = "Monte-Carlo ray-traced AO with Embree (the reference algorithm at a chosen cost)";
  info.paper =
      "the aoeval reference (CONTRACT §3): cosine or uniform hemisphere sampling, first hit";
  info.backend = Backend::embree;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = {
      int_param({.name = "rays",
                 .def = 16,
                 .min = 1,
                 .max = 65536,
                 .spacing = Spacing::log,
                 .unit = "rays",
                 .meaning = "rays per pixel"}),
      choice_param({.name = "weighting",
                    .def = "cosine",
                    .choices = {"cosine", "uniform"},
                    .meaning = "direction weighting: cosine (Dimitrov et al. eq. 1) or uniform "
                               "(Hegeman et al. eq. 3)"}),
      real_param({.name = "dmax",
                  .def = 0.0,
                  .min = 0.0,
                  .max = 1e6,
                  .spacing = Spacing::linear,
                  .unit = "scene units",
                  .meaning = "occluder range; 0 = unbounded (CONTRACT §3)"}),
      choice_param(
          {.name = "sampler",
           .def = "random",
           .choices = {"random", "stratified", "sobol"},
           .meaning =
               "random, stratified (Mendez et al. §4.2 systematic) or sobol (Owen-scrambled)"}),
      seed_param("random seed (the references use 1, so the two never share samples)"),
  };
  // falloff and falloff_k after dmax: the declaration rtao shares (power_falloff_param.h).
  const std::vector<ParamSpec> falloff = falloff_params("dmax");
  info.params.insert(info.params.begin() + 3, falloff.begin(), falloff.end());
  info.definition_doc = "weighting, dmax and falloff as its parameters say";
  info.definition = definition_of;
  info.create = [](const ParamSet& p) { return std::make_unique<RaytracedEstimator>(p); };
  return info;
}

}  // namespace aoeval
