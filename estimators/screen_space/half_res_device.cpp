// Half resolution on the device: see half_res_device.h and, for the algorithm, half_res.glsl.
#include "estimators/screen_space/half_res_device.h"

#include "estimators/vulkan/vk_pipelines.h"
#include "half_res_down_comp_spv.h"
#include "half_res_up_comp_spv.h"

namespace aoeval {

namespace {
constexpr uint32_t kGroup = 8;  // the local size of both shaders
const VkDescriptorType kImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
}  // namespace

struct HalfResDevice::Impl {
  const ScreenSpaceFrameDevice& full;
  ScreenSpaceFrame shape;
  HalfResConstants constants{};
  vk::Image2D depth, normal, ao, vector, unused;  // unused: the vector slots when vector = 0
  vk::ComputePipeline down, up;
  VkDescriptorSet down_set = VK_NULL_HANDLE, up_set = VK_NULL_HANDLE;

  Impl(vk::Context& vk, const ScreenSpaceFrameDevice& f, bool with_vector)
      : full(f),
        shape(half_resolution_shape(shape_of_full(f))),
        constants(half_res_constants(shape_of_full(f), with_vector)),
        depth(vk, shape.width, shape.height, VK_FORMAT_R32_SFLOAT),
        normal(vk, shape.width, shape.height, VK_FORMAT_R32G32B32A32_SFLOAT),
        ao(vk, f.width(), f.height(), VK_FORMAT_R32_SFLOAT),
        vector(vk, with_vector ? f.width() : 1, with_vector ? f.height() : 1,
               VK_FORMAT_R32G32B32A32_SFLOAT),
        unused(vk, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT),
        down(vk, "half-resolution downsample", half_res_down_comp_spv,
             {kImage, kImage, kImage, kImage}, sizeof(HalfResConstants)),
        up(vk, "half-resolution upsample", half_res_up_comp_spv,
           {kImage, kImage, kImage, kImage, kImage, kImage}, sizeof(HalfResConstants)) {
    down_set = down.make_set({full.depth(), full.normal(), depth, normal});
  }

  static ScreenSpaceFrame shape_of_full(const ScreenSpaceFrameDevice& f) {
    ScreenSpaceFrame s;
    s.width = f.width();
    s.height = f.height();
    s.focal = f.focal();
    return s;
  }
};

HalfResDevice::HalfResDevice(vk::Context& vk, const ScreenSpaceFrameDevice& full, bool vector)
    : impl_(std::make_unique<Impl>(vk, full, vector)) {}

HalfResDevice::~HalfResDevice() = default;

const ScreenSpaceFrame& HalfResDevice::shape() const {
  return impl_->shape;
}
const vk::Image2D& HalfResDevice::depth() const {
  return impl_->depth;
}
const vk::Image2D& HalfResDevice::normal() const {
  return impl_->normal;
}
const vk::Image2D& HalfResDevice::ao() const {
  return impl_->ao;
}
const vk::Image2D& HalfResDevice::vector() const {
  return impl_->vector;
}

void HalfResDevice::bind(const vk::Image2D& low_ao, const vk::Image2D* low_vector) {
  Impl& m = *impl_;
  const bool with_vector = m.constants.vector != 0;
  m.up_set = m.up.make_set({m.full.depth(), m.full.normal(), low_ao,
                            with_vector && low_vector ? *low_vector : m.unused, m.ao,
                            with_vector ? m.vector : m.unused});
}

void HalfResDevice::record_downsample(VkCommandBuffer cmd, vk::PassTimer& timer) {
  Impl& m = *impl_;
  vk::timed_compute_pass(cmd, timer, "downsample", m.down, m.down_set, m.constants,
                         vk::group_count(static_cast<uint32_t>(m.shape.width), kGroup),
                         vk::group_count(static_cast<uint32_t>(m.shape.height), kGroup));
}

void HalfResDevice::record_upsample(VkCommandBuffer cmd, vk::PassTimer& timer) {
  Impl& m = *impl_;
  vk::timed_compute_pass(cmd, timer, "upsample", m.up, m.up_set, m.constants,
                         vk::group_count(static_cast<uint32_t>(m.constants.width), kGroup),
                         vk::group_count(static_cast<uint32_t>(m.constants.height), kGroup));
}

}  // namespace aoeval
