#include "estimators/constant/constant.h"

namespace aoeval {

namespace {

class ConstantEstimator : public Estimator {
 public:
  explicit ConstantEstimator(float value) : value_(value) {}
  EstimateResult run(const EstimateContext& context) override {
    EstimateResult r;
    r.ao.assign(context.gbuffer.pixel_count(), value_);
    return r;
  }

 private:
  float value_;
};

}  // namespace

EstimatorInfo constant_estimator() {
  EstimatorInfo info;
  info.name = "constant";
  info.summary = "AO = value everywhere: ambient light only";
  info.paper =
      "Hegeman, Premoze, Ashikhmin, Drettakis 2006, Approximate Ambient Occlusion for Trees, "
      "Fig. 12 bottom row (ambient term only)";
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer};
  info.params = {
      real_param({.name = "value",
                  .def = 1.0,
                  .min = 0.0,
                  .max = 1.0,
                  .spacing = Spacing::linear,
                  .unit = "",
                  .meaning = "the AO every pixel gets (1 = ambient only, no occlusion)"})};
  info.definition_doc = "cosine-weighted, unbounded (it stands in for true AO)";
  info.definition = [](const ParamSet&) { return AoDefinition{}; };
  info.create = [](const ParamSet& p) {
    return std::make_unique<ConstantEstimator>(static_cast<float>(p.real("value")));
  };
  return info;
}

}  // namespace aoeval
