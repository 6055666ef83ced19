// hbao-split-cpu: the CPU twin of hbao-split. It compiles the shared kernel (hbao_kernel.glsl) as
// C++ and runs its three passes (horizon occlusion, normal occlusion, blur) with TBB over rows.
#include <atomic>
#include <chrono>

#include "estimators/pixel_loops.h"

#include "base/errors.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/screen_space/half_res.h"

// The kernel, compiled twice: `plain` for frames, `counting` (the same text with a depth accessor
// that counts) for the benchmark's fetch count, so the plain loop carries no counter.
#include "estimators/hbao_split/hbao_cpu_kernel.h"

namespace aoeval::hbao_glsl {

namespace plain {
inline float hbao_depth(const HbaoImages& img, int i, int j) {
  return img.depth[pixel_of(img, i, j)];
}
#include "estimators/hbao_split/hbao_kernel.glsl"
}  // namespace plain

namespace counting {
inline float hbao_depth(const HbaoImages& img, int i, int j) {
  ++*img.fetches;
  return img.depth[pixel_of(img, i, j)];
}
#include "estimators/hbao_split/hbao_kernel.glsl"
}  // namespace counting

}  // namespace aoeval::hbao_glsl

#include "estimators/hbao_split/hbao_cpu_kernel_end.h"

namespace aoeval {

using Clock = std::chrono::steady_clock;

namespace {

// The passes at the frame's own resolution.
HbaoCpuResult hbao_passes(const ScreenSpaceFrame& frame, const HbaoSettings& settings,
                          bool count_fetches) {
  const int w = frame.width, h = frame.height;
  const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);
  const HbaoConstants c = hbao_constants(settings, frame);
  const std::vector<glm::vec3> random = hbao_random_texture(settings);
  const std::vector<glm::vec2> directions = hbao_direction_table(settings.directions);
  std::vector<float> horizon(pixels * static_cast<size_t>(settings.directions), 0.0f);
  std::vector<float> ot(pixels, 0.0f);

  HbaoCpuResult out;
  out.raw_ao.assign(pixels, 0.0f);
  out.horizon_ao.assign(pixels, 0.0f);
  hbao_glsl::HbaoImages images;
  images.width = w;
  images.pixels = pixels;
  images.depth = frame.depth.data();
  images.normal = frame.normal.data();
  images.random = random.data();
  images.tile = settings.tile;
  images.directions = directions.data();
  images.raw_ao = out.raw_ao.data();
  images.horizon = horizon.data();

  std::atomic<uint64_t> fetches{0};
  // Each row range counts into its own counter, added once at the end of the range.
  auto counted = [&](auto&& pass) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& rows) {
      uint64_t local = 0;
      hbao_glsl::HbaoImages mine = images;
      mine.fetches = &local;
      for (int j = rows.begin(); j < rows.end(); ++j)
        for (int i = 0; i < w; ++i) pass(mine, i, j);
      fetches += local;
    });
  };

  auto t0 = Clock::now();
  if (count_fetches) {
    counted([&](const hbao_glsl::HbaoImages& img, int i, int j) {
      ot[img.width * static_cast<size_t>(j) + i] =
          hbao_glsl::counting::hbao_horizon_pass(img, i, j, c);
    });
  } else {
    for_each_pixel(w, h, [&](int i, int j) {
      ot[frame.width * static_cast<size_t>(j) + i] =
          hbao_glsl::plain::hbao_horizon_pass(images, i, j, c);
    });
  }
  out.horizon_ms = ms_since(t0);

  t0 = Clock::now();
  if (count_fetches) {
    counted([&](const hbao_glsl::HbaoImages& img, int i, int j) {
      const size_t k = img.width * static_cast<size_t>(j) + i;
      out.raw_ao[k] = hbao_glsl::counting::hbao_normal_pass(img, i, j, ot[k], c);
    });
  } else {
    for_each_pixel(w, h, [&](int i, int j) {
      const size_t k = frame.width * static_cast<size_t>(j) + i;
      out.raw_ao[k] = hbao_glsl::plain::hbao_normal_pass(images, i, j, ot[k], c);
    });
  }
  out.normal_ms = ms_since(t0);
  for (size_t k = 0; k < pixels; ++k)
    out.horizon_ao[k] = frame.depth[k] > 0.0f ? 1.0f - ot[k] : 0.0f;

  t0 = Clock::now();
  if (settings.blur) {
    out.ao.assign(pixels, 0.0f);
    for_each_pixel(w, h, [&](int i, int j) {
      out.ao[frame.width * static_cast<size_t>(j) + i] =
          hbao_glsl::plain::hbao_blur(images, i, j, c);
    });
  } else {
    out.ao = out.raw_ao;
  }
  out.blur_ms = ms_since(t0);
  out.depth_fetches = fetches.load();
  return out;
}

}  // namespace

HbaoCpuResult hbao_split_cpu(const ScreenSpaceFrame& frame, const HbaoSettings& settings,
                             bool count_fetches) {
  validate_hbao_frame(frame);
  if (!settings.half_res) return hbao_passes(frame, settings, count_fetches);
  auto t0 = Clock::now();
  const ScreenSpaceFrame low = half_resolution_frame(frame);
  const double downsample_ms = ms_since(t0);
  HbaoCpuResult out = hbao_passes(low, settings, count_fetches);
  out.downsample_ms = downsample_ms;
  t0 = Clock::now();
  out.ao = upsample_half_res(frame, out.ao);
  out.upsample_ms = ms_since(t0);
  out.horizon_ao = upsample_half_res(frame, out.horizon_ao);  // a diagnostic: not timed
  return out;
}

namespace {

class HbaoCpuEstimator : public Estimator {
 public:
  explicit HbaoCpuEstimator(const ParamSet& p) : settings_(hbao_settings_of(p)) {}
  void prepare(const EstimateContext& context) override {
    settings_.frame = noise_frame(context);  // the random texture of seed + k
    frame_ = screen_space_frame_from_gbuffer(context.gbuffer);
    prepared_ = true;
  }
  EstimateResult run(const EstimateContext& context) override {
    if (!prepared_) prepare(context);
    HbaoCpuResult image = hbao_split_cpu(frame_, settings_);
    EstimateResult r;
    r.ao = std::move(image.ao);
    r.extra_channels["AO_horizon"] = std::move(image.horizon_ao);
    r.pass_ms = {{"horizon_ms", image.horizon_ms},
                 {"normal_ms", image.normal_ms},
                 {"blur_ms", image.blur_ms}};
    if (settings_.half_res) {
      r.pass_ms["downsample_ms"] = image.downsample_ms;
      r.pass_ms["upsample_ms"] = image.upsample_ms;
    }
    return r;
  }

 private:
  HbaoSettings settings_;
  ScreenSpaceFrame frame_;
  bool prepared_ = false;
};

}  // namespace

EstimatorInfo hbao_split_cpu_estimator() {
  EstimatorInfo info;
  info.name = "hbao-split-cpu";
  info.summary =
      "horizon-split SSAO on the CPU (TBB over rows): the same kernel source and random texture "
      "as hbao-split";
  info.paper = kHbaoPaper;
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer};
  info.params = hbao_param_specs();
  info.definition_doc = kHbaoDefinitionDoc;
  info.definition = [](const ParamSet& p) { return hbao_definition(hbao_settings_of(p)); };
  info.create = [](const ParamSet& p) {
    return hbao_over_time(std::make_unique<HbaoCpuEstimator>(p), hbao_settings_of(p));
  };
  info.keeps_state = true;  // draws frame k's random texture itself (HbaoSettings::frame)
  return info;
}

}  // namespace aoeval
