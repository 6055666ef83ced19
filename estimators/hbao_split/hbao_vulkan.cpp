// hbao-split: the Vulkan twin (see hbao_vulkan.h and, for the algorithm, hbao_split.h).
#include "estimators/hbao_split/hbao_vulkan.h"

#include <cmath>
#include <glm/vec4.hpp>
#include <numbers>

#include "estimators/screen_space/frame_device.h"
#include "estimators/screen_space/half_res_device.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "hbao_bare_fetch_comp_spv.h"
#include "hbao_blur_comp_spv.h"
#include "hbao_horizon_comp_spv.h"
#include "hbao_normal_comp_spv.h"

namespace aoeval {

namespace {

constexpr auto kGroup = static_cast<uint32_t>(kHbaoGroupSize);

// hbao_common.glsl's bindings, in order.
const std::vector<VkDescriptorType> kPassBindings = {
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 0 depth
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 1 eye-space normal
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 2 random texture
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 3 directions
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 4 horizons
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 5 O_T
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 6 raw AO
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 7 AO
};

}  // namespace

struct HbaoDevice::Impl {
  vk::Context& vk;
  HbaoSettings settings{};
  HbaoConstants constants{};
  int width = 0, height = 0;
  std::unique_ptr<ScreenSpaceFrameDevice> frame;  // depth and eye normals, uploaded or rasterised
  std::unique_ptr<HalfResDevice> half;            // resolution = half: the passes run on its frame
  vk::Image2D ot, raw_ao, ao;
  vk::Buffer random, directions, horizons;
  std::unique_ptr<vk::ComputePipeline> horizon, normal_pass, blur;
  VkDescriptorSet horizon_set = VK_NULL_HANDLE, normal_set = VK_NULL_HANDLE,
                  blur_set = VK_NULL_HANDLE;
  vk::PassTimer timer;

  // `full`: the frame's shape; the passes' images have the computed resolution's.
  Impl(vk::Context& context, const HbaoSettings& s, const ScreenSpaceFrame& full)
      : vk(context), settings(s), timer(context) {
    const ScreenSpaceFrame shape = s.half_res ? half_resolution_shape(full) : full;
    const int w = shape.width, h = shape.height;
    width = w;
    height = h;
    constants = hbao_constants(s, shape);
    ot = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    raw_ao = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    ao = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    random = vk::storage_buffer(vk, padded_texels(hbao_random_texture(s)));
    directions = vk::storage_buffer(vk, hbao_direction_table(s.directions));
    horizons = vk::Buffer(vk, static_cast<VkDeviceSize>(w) * h * s.directions * sizeof(float),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  }

  void make_pipelines() {
    const uint32_t push = sizeof(HbaoConstants);
    horizon = std::make_unique<vk::ComputePipeline>(vk, "hbao horizon", hbao_horizon_comp_spv,
                                                    kPassBindings, push);
    normal_pass = std::make_unique<vk::ComputePipeline>(vk, "hbao normal", hbao_normal_comp_spv,
                                                        kPassBindings, push);
    blur = std::make_unique<vk::ComputePipeline>(vk, "hbao blur", hbao_blur_comp_spv, kPassBindings,
                                                 push);
    if (settings.half_res) half = std::make_unique<HalfResDevice>(vk, *frame, false);
    const vk::Image2D& depth = half ? half->depth() : frame->depth();
    const vk::Image2D& normal = half ? half->normal() : frame->normal();
    const std::vector<vk::Resource> resources = {depth,    normal, random, directions,
                                                 horizons, ot,     raw_ao, ao};
    horizon_set = horizon->make_set(resources);
    normal_set = normal_pass->make_set(resources);
    blur_set = blur->make_set(resources);
    if (half) half->bind(settings.blur ? ao : raw_ao, nullptr);
  }
};

HbaoDevice::HbaoDevice(vk::Context& vk, const HbaoSettings& settings, const ScreenSpaceFrame& frame,
                       const Camera& camera) {
  validate_hbao_frame(frame);
  check_frame_matches_camera(frame, camera);
  impl_ = std::make_unique<Impl>(vk, settings, frame);
  impl_->frame = std::make_unique<ScreenSpaceFrameDevice>(vk, frame);
  impl_->make_pipelines();
}

HbaoDevice::HbaoDevice(vk::Context& vk, const HbaoSettings& settings, const Scene& scene,
                       const Camera& camera) {
  const ScreenSpaceFrame shape = screen_space_frame_shape(camera);
  validate_hbao_frame(shape);
  impl_ = std::make_unique<Impl>(vk, settings, shape);
  impl_->frame = std::make_unique<ScreenSpaceFrameDevice>(vk, scene, camera);
  impl_->make_pipelines();
}

HbaoDevice::~HbaoDevice() = default;

const vk::Image2D& HbaoDevice::depth_image() const {
  return impl_->frame->depth();
}

HbaoGpuResult HbaoDevice::run() {
  Impl& m = *impl_;
  const uint32_t gx = vk::group_count(static_cast<uint32_t>(m.width), kGroup);
  const uint32_t gy = vk::group_count(static_cast<uint32_t>(m.height), kGroup);
  m.vk.submit([&](VkCommandBuffer cmd) {
    m.timer.reset(cmd);
    m.frame->record(cmd, m.timer);  // the geometry stage with gbuffer=raster
    if (m.half) m.half->record_downsample(cmd, m.timer);
    vk::timed_compute_pass(cmd, m.timer, "horizon", *m.horizon, m.horizon_set, m.constants, gx, gy);
    vk::timed_compute_pass(cmd, m.timer, "normal", *m.normal_pass, m.normal_set, m.constants, gx,
                           gy);
    if (m.settings.blur)
      vk::timed_compute_pass(cmd, m.timer, "blur", *m.blur, m.blur_set, m.constants, gx, gy);
    if (m.half) m.half->record_upsample(cmd, m.timer);
  });
  HbaoGpuResult r;
  r.pass_ms = m.timer.read();
  r.raw_ao = m.raw_ao.download<float>();
  r.ao = m.half            ? m.half->ao().download<float>()
         : m.settings.blur ? m.ao.download<float>()
                           : r.raw_ao;
  const std::vector<float> ot = m.ot.download<float>();
  const std::vector<float> z = (m.half ? m.half->depth() : m.frame->depth()).download<float>();
  r.horizon_ao.assign(ot.size(), 0.0f);
  for (size_t k = 0; k < ot.size(); ++k) r.horizon_ao[k] = z[k] > 0.0f ? 1.0f - ot[k] : 0.0f;
  // At half resolution the horizon term (a diagnostic channel) is upsampled on the host.
  if (m.half) r.horizon_ao = upsample_half_res(m.frame->download(), r.horizon_ao);
  return r;
}

ScreenSpaceFrame HbaoDevice::frame() const {
  return impl_->frame->download();
}

struct BareFetch::Impl {
  struct Push {
    int32_t width, height, walks, steps;
  };
  vk::Context& vk;
  Push push;
  uint32_t groups_x, groups_y;
  vk::Buffer walk_buffer;
  vk::Image2D sums;
  vk::ComputePipeline pipeline;
  VkDescriptorSet set;
  vk::PassTimer timer;

  static std::vector<glm::vec2> walk_table(int walks, float step_px) {
    std::vector<glm::vec2> table(static_cast<size_t>(walks));
    for (int w = 0; w < walks; ++w) {
      const double a = 2.0 * std::numbers::pi * (w + 0.5) / walks;
      table[static_cast<size_t>(w)] = glm::vec2(static_cast<float>(step_px * std::cos(a)),
                                                static_cast<float>(step_px * std::sin(a)));
    }
    return table;
  }

  Impl(vk::Context& context, const vk::Image2D& depth, int walks, int steps, float step_px)
      : vk(context),
        push{depth.width(), depth.height(), walks, steps},
        groups_x(vk::group_count(static_cast<uint32_t>(depth.width()), kGroup)),
        groups_y(vk::group_count(static_cast<uint32_t>(depth.height()), kGroup)),
        walk_buffer(vk, static_cast<VkDeviceSize>(walks) * sizeof(glm::vec2),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
        sums(vk, depth.width(), depth.height(), VK_FORMAT_R32_SFLOAT),
        pipeline(vk, "hbao bare fetch", hbao_bare_fetch_comp_spv,
                 {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                 sizeof(Push)),
        set(VK_NULL_HANDLE),
        timer(vk) {
    walk_buffer.upload(walk_table(walks, step_px));
    set = pipeline.make_set({depth, sums, walk_buffer});
  }
};

BareFetch::BareFetch(vk::Context& vk, const vk::Image2D& depth, int walks, int steps, float step_px)
    : impl_(std::make_unique<Impl>(vk, depth, walks, steps, step_px)) {}

BareFetch::~BareFetch() = default;

double BareFetch::run_ms() {
  Impl& m = *impl_;
  m.vk.submit([&](VkCommandBuffer cmd) {
    m.timer.reset(cmd);
    m.timer.begin(cmd, "bare");
    m.pipeline.dispatch(cmd, m.set, m.push, m.groups_x, m.groups_y);
    m.timer.end(cmd);
  });
  return m.timer.read().at("bare_ms");
}

namespace {

// One frame of hbao-split as the harness sees it: AO, the horizon term as an extra channel, and
// the passes' GPU times.
EstimateResult hbao_frame_result(const HbaoSettings&, HbaoDevice& device) {
  HbaoGpuResult image = device.run();
  EstimateResult r;
  r.ao = std::move(image.ao);
  r.extra_channels["AO_horizon"] = std::move(image.horizon_ao);
  r.pass_ms = std::move(image.pass_ms);
  return r;
}

}  // namespace

EstimatorInfo hbao_split_estimator() {
  EstimatorInfo info;
  info.name = "hbao-split";
  info.summary =
      "horizon-split SSAO on Vulkan: horizon, normal-occlusion and blur compute passes, GPU "
      "timestamps per pass";
  info.paper = kHbaoPaper;
  info.backend = Backend::vulkan;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = hbao_param_specs();
  info.params.push_back(frame_source_param("§5's geometry pass"));
  info.definition_doc = kHbaoDefinitionDoc;
  info.definition = [](const ParamSet& p) { return hbao_definition(hbao_settings_of(p)); };
  info.create = [](const ParamSet& p) {
    return hbao_over_time(std::make_unique<FrameDeviceEstimator<HbaoDevice, HbaoSettings>>(
                              hbao_settings_of(p), rasterises_frame(p), hbao_frame_result),
                          hbao_settings_of(p));
  };
  info.keeps_state = true;  // draws frame k's random texture itself (HbaoSettings::frame)
  return info;
}

}  // namespace aoeval
