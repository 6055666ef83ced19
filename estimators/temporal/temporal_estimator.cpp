#include "estimators/temporal/temporal_estimator.h"

#include <chrono>

namespace aoeval {

namespace {

class TemporalStageEstimator : public Estimator {
 public:
  TemporalStageEstimator(std::unique_ptr<Estimator> inner, const TemporalSettings& settings)
      : inner_(std::move(inner)), stage_(settings) {}

  void prepare(const EstimateContext& context) override {
    still_ = context.frame == nullptr;
    inner_->prepare(context);
  }

  EstimateResult run(const EstimateContext& context) override {
    EstimateResult r = inner_->run(context);
    const auto t0 = std::chrono::steady_clock::now();
    // A still view repeats (the harness times it several times): no history carried over.
    if (!context.frame || context.frame->index == 0) stage_.reset();
    stage_.accumulate(context.gbuffer, r.ao);
    r.extra_channels["AO_frame"] = std::move(r.ao);
    r.ao = stage_.value();
    r.extra_channels["history_length"] = stage_.history_length();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    r.pass_ms["temporal_ms"] = ms;
    if (auto total = r.pass_ms.find("total_ms"); total != r.pass_ms.end()) total->second += ms;
    return r;
  }

  nlohmann::json derived() const override {
    nlohmann::json d = inner_->derived();
    if (still_)
      d["temporal"] =
          "still frame: frame 0 of the temporal stage, no history (a sequence view accumulates)";
    return d;
  }

 private:
  std::unique_ptr<Estimator> inner_;
  TemporalAccumulator stage_;
  bool still_ = true;
};

}  // namespace

std::unique_ptr<Estimator> with_temporal_stage(std::unique_ptr<Estimator> inner,
                                               const TemporalSettings& settings) {
  return std::make_unique<TemporalStageEstimator>(std::move(inner), settings);
}

}  // namespace aoeval
