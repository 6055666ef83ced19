// gtao-cpu: the CPU twin of gtao. It compiles the shared kernel (gtao_kernel.glsl) as C++ and runs
// its two passes (horizons and integrals, denoise) with TBB over rows.
#include <chrono>

#include "estimators/pixel_loops.h"

#include "estimators/gtao/gtao.h"
#include "estimators/gtao/gtao_cpu_kernel.h"
#include "estimators/screen_space/half_res.h"

namespace aoeval {

using Clock = std::chrono::steady_clock;

GtaoOutput gtao_cpu(const ScreenSpaceFrame& full, const Camera& camera,
                    const GtaoSettings& settings) {
  validate_gtao_frame(full);
  GtaoOutput out;
  auto t0 = Clock::now();
  // resolution = half: the passes below run on the half-resolution frame (half_res.h).
  const ScreenSpaceFrame low = settings.half_res ? half_resolution_frame(full) : ScreenSpaceFrame{};
  if (settings.half_res) {
    validate_gtao_frame(low);
    out.pass_ms["downsample_ms"] = ms_since(t0);
  }
  const ScreenSpaceFrame& frame = settings.half_res ? low : full;
  const int w = frame.width, h = frame.height;
  const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
  const GtaoConstants c = gtao_constants(settings, frame);
  const GtaoTables tables = gtao_tables(settings);
  std::vector<float> raw_ao(pixels, 0.0f);
  std::vector<glm::vec3> raw_bent(pixels, glm::vec3(0.0f));

  gtao_glsl::GtaoImages images;
  images.width = w;
  images.tile = settings.tile;
  images.steps = settings.steps;
  images.depth = frame.depth.data();
  images.normal = frame.normal.data();
  images.rotation = tables.rotation.data();
  images.step = tables.steps.data();
  images.slice = tables.slices.data();
  images.raw_ao = raw_ao.data();
  images.raw_bent = raw_bent.data();

  t0 = Clock::now();
  for_each_pixel(w, h, [&](int i, int j) {
    const size_t k = static_cast<size_t>(j) * static_cast<size_t>(w) + static_cast<size_t>(i);
    raw_ao[k] = gtao_glsl::gtao_pixel(images, i, j, c, raw_bent[k]);
  });
  out.pass_ms["horizon_ms"] = ms_since(t0);

  std::vector<float> ao;
  std::vector<glm::vec3> bent;
  if (settings.denoise) {
    t0 = Clock::now();
    ao.assign(pixels, 0.0f);
    bent.assign(pixels, glm::vec3(0.0f));
    for_each_pixel(w, h, [&](int i, int j) {
      const size_t k = static_cast<size_t>(j) * static_cast<size_t>(w) + static_cast<size_t>(i);
      ao[k] = gtao_glsl::gtao_denoise(images, i, j, c, bent[k]);
    });
    out.pass_ms["denoise_ms"] = ms_since(t0);
  } else {
    ao = raw_ao;
    bent = raw_bent;
  }
  if (settings.half_res) {
    t0 = Clock::now();
    ao = upsample_half_res(full, ao);
    if (settings.bent) bent = upsample_half_res(full, bent);
    out.pass_ms["upsample_ms"] = ms_since(t0);
  }
  out.raw_ao = std::move(raw_ao);
  gtao_finish(settings, camera, full, ao, bent, out);
  return out;
}

namespace {

class GtaoCpuEstimator : public Estimator {
 public:
  explicit GtaoCpuEstimator(const ParamSet& p) : settings_(gtao_settings_of(p)) {}
  void prepare(const EstimateContext& context) override {
    settings_.frame = noise_frame(context);  // the noise of frame k (gtao_noise_of)
    still_ = context.frame == nullptr;
    frame_ = screen_space_frame_from_gbuffer(context.gbuffer);
    prepared_ = true;
  }
  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    return gtao_estimate_result(settings_, gtao_cpu(frame_, context.gbuffer.camera, settings_));
  }
  nlohmann::json derived() const override { return frame_derived(settings_, still_); }

 private:
  GtaoSettings settings_;
  ScreenSpaceFrame frame_;
  bool prepared_ = false;
  bool still_ = true;
};

}  // namespace

EstimatorInfo gtao_cpu_estimator() {
  EstimatorInfo info;
  info.name = "gtao-cpu";
  info.summary =
      "ground-truth AO (GTAO) on the CPU (TBB over rows): the same kernel source and noise as gtao";
  info.paper = kGtaoPaper;
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer};
  info.params = gtao_param_specs();
  info.definition_doc = kGtaoDefinitionDoc;
  info.definition = [](const ParamSet& p) { return gtao_definition(gtao_settings_of(p)); };
  info.create = [](const ParamSet& p) {
    return gtao_over_time(std::make_unique<GtaoCpuEstimator>(p), gtao_settings_of(p));
  };
  info.keeps_state = true;  // draws frame k's noise itself (gtao_noise_of)
  return info;
}

}  // namespace aoeval
