// gtao: the Vulkan twin (see gtao_vulkan.h and, for the algorithm, gtao.h).
#include "estimators/gtao/gtao_vulkan.h"

#include <glm/vec4.hpp>

#include "estimators/screen_space/frame_device.h"
#include "estimators/screen_space/half_res_device.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "estimators/vulkan/vk_resources.h"
#include "gtao_denoise_comp_spv.h"
#include "gtao_main_comp_spv.h"

namespace aoeval {

namespace {

constexpr auto kGroup = static_cast<uint32_t>(kGtaoGroupSize);

// gtao_common.glsl's bindings, in order.
const std::vector<VkDescriptorType> kPassBindings = {
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 0 depth
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 1 eye-space normal
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 2 rotation
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 3 steps
    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,  // 4 slices
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 5 raw AO
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 6 raw bent
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 7 AO
    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,   // 8 bent
};

}  // namespace

struct GtaoDevice::Impl {
  vk::Context& vk;
  GtaoSettings settings;
  GtaoConstants constants{};
  Camera camera;
  int width = 0, height = 0;
  std::unique_ptr<ScreenSpaceFrameDevice> frame;  // depth and eye normals, uploaded or rasterised
  std::unique_ptr<HalfResDevice> half;            // resolution = half: the passes run on its frame
  vk::Image2D raw_ao, raw_bent, ao, bent;
  vk::Buffer rotation, steps, slices;
  std::unique_ptr<vk::ComputePipeline> main_pass, denoise;
  VkDescriptorSet main_set = VK_NULL_HANDLE, denoise_set = VK_NULL_HANDLE;
  vk::PassTimer timer;

  // `full`: the frame's shape; the passes' images have the computed resolution's.
  Impl(vk::Context& context, const GtaoSettings& s, const Camera& cam, const ScreenSpaceFrame& full)
      : vk(context), settings(s), camera(cam), timer(context) {
    const ScreenSpaceFrame shape = s.half_res ? half_resolution_shape(full) : full;
    validate_gtao_frame(shape);
    const int w = shape.width, h = shape.height;
    width = w;
    height = h;
    constants = gtao_constants(s, shape);
    raw_ao = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    raw_bent = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
    ao = vk::Image2D(vk, w, h, VK_FORMAT_R32_SFLOAT);
    bent = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
    const GtaoTables tables = gtao_tables(s);
    rotation = vk::storage_buffer(vk, tables.rotation);
    steps = vk::storage_buffer(vk, tables.steps);
    slices = vk::storage_buffer(vk, tables.slices);
  }

  void make_pipelines() {
    const uint32_t push = sizeof(GtaoConstants);
    main_pass = std::make_unique<vk::ComputePipeline>(vk, "gtao main", gtao_main_comp_spv,
                                                      kPassBindings, push);
    denoise = std::make_unique<vk::ComputePipeline>(vk, "gtao denoise", gtao_denoise_comp_spv,
                                                    kPassBindings, push);
    if (settings.half_res) half = std::make_unique<HalfResDevice>(vk, *frame, settings.bent);
    const vk::Image2D& depth = half ? half->depth() : frame->depth();
    const vk::Image2D& normal = half ? half->normal() : frame->normal();
    const std::vector<vk::Resource> resources = {depth,  normal,   rotation, steps, slices,
                                                 raw_ao, raw_bent, ao,       bent};
    main_set = main_pass->make_set(resources);
    denoise_set = denoise->make_set(resources);
    if (half) {
      const bool d = settings.denoise;
      half->bind(d ? ao : raw_ao, settings.bent ? (d ? &bent : &raw_bent) : nullptr);
    }
  }
};

GtaoDevice::GtaoDevice(vk::Context& vk, const GtaoSettings& settings, const ScreenSpaceFrame& frame,
                       const Camera& camera) {
  validate_gtao_frame(frame);
  check_frame_matches_camera(frame, camera);
  impl_ = std::make_unique<Impl>(vk, settings, camera, frame);
  impl_->frame = std::make_unique<ScreenSpaceFrameDevice>(vk, frame);
  impl_->make_pipelines();
}

GtaoDevice::GtaoDevice(vk::Context& vk, const GtaoSettings& settings, const Scene& scene,
                       const Camera& camera) {
  const ScreenSpaceFrame shape = screen_space_frame_shape(camera);
  validate_gtao_frame(shape);
  impl_ = std::make_unique<Impl>(vk, settings, camera, shape);
  impl_->frame = std::make_unique<ScreenSpaceFrameDevice>(vk, scene, camera);
  impl_->make_pipelines();
}

GtaoDevice::~GtaoDevice() = default;

GtaoOutput GtaoDevice::run() {
  Impl& m = *impl_;
  const uint32_t gx = vk::group_count(static_cast<uint32_t>(m.width), kGroup);
  const uint32_t gy = vk::group_count(static_cast<uint32_t>(m.height), kGroup);
  m.vk.submit([&](VkCommandBuffer cmd) {
    m.timer.reset(cmd);
    m.frame->record(cmd, m.timer);  // the geometry stage with gbuffer=raster
    if (m.half) m.half->record_downsample(cmd, m.timer);
    vk::timed_compute_pass(cmd, m.timer, "horizon", *m.main_pass, m.main_set, m.constants, gx, gy);
    if (m.settings.denoise)
      vk::timed_compute_pass(cmd, m.timer, "denoise", *m.denoise, m.denoise_set, m.constants, gx,
                             gy);
    if (m.half) m.half->record_upsample(cmd, m.timer);
  });
  GtaoOutput out;
  out.pass_ms = m.timer.read();
  out.raw_ao = m.raw_ao.download<float>();
  const vk::Image2D& final_ao = m.half ? m.half->ao() : m.settings.denoise ? m.ao : m.raw_ao;
  const vk::Image2D& final_bent = m.half               ? m.half->vector()
                                  : m.settings.denoise ? m.bent
                                                       : m.raw_bent;
  std::vector<float> ao = final_ao.download<float>();
  std::vector<glm::vec3> eye_bent;
  if (m.settings.bent) eye_bent = unpadded_texels(final_bent.download<float>());
  const ScreenSpaceFrame seen = frame();
  gtao_finish(m.settings, m.camera, seen, ao, eye_bent, out);
  return out;
}

ScreenSpaceFrame GtaoDevice::frame() const {
  return impl_->frame->download();
}

namespace {

EstimateResult gtao_frame_result(const GtaoSettings& settings, GtaoDevice& device) {
  return gtao_estimate_result(settings, device.run());
}

}  // namespace

EstimatorInfo gtao_estimator() {
  EstimatorInfo info;
  info.name = "gtao";
  info.summary =
      "ground-truth AO (GTAO) on Vulkan: horizon-and-integral and denoise compute passes, bent "
      "normals, GPU timestamps per pass";
  info.paper = kGtaoPaper;
  info.backend = Backend::vulkan;
  info.inputs = {EstimatorInput::gbuffer, EstimatorInput::scene_geometry};
  info.params = gtao_param_specs();
  info.params.push_back(frame_source_param(""));
  info.definition_doc = kGtaoDefinitionDoc;
  info.definition = [](const ParamSet& p) { return gtao_definition(gtao_settings_of(p)); };
  info.create = [](const ParamSet& p) {
    const GtaoSettings s = gtao_settings_of(p);
    return gtao_over_time(std::make_unique<FrameDeviceEstimator<GtaoDevice, GtaoSettings>>(
                              s, rasterises_frame(p), gtao_frame_result),
                          s);
  };
  info.keeps_state = true;  // draws frame k's noise itself (Settings::frame)
  return info;
}

}  // namespace aoeval
