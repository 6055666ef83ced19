#include "estimators/screen_space/frame_device.h"

#include <glm/vec4.hpp>

#include "base/errors.h"
#include "estimators/vulkan/raster_gbuffer.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "eye_normals_comp_spv.h"

namespace aoeval {

namespace {

constexpr uint32_t kEyeNormalsGroup = 8;  // eye_normals.comp's local size

struct EyeNormalsPush {
  glm::vec4 right, up, forward;
  int32_t width, height;
};

}  // namespace

std::vector<glm::vec4> padded_texels(const std::vector<glm::vec3>& v) {
  std::vector<glm::vec4> out(v.size());
  for (size_t k = 0; k < v.size(); ++k) out[k] = glm::vec4(v[k], 0.0f);
  return out;
}

std::vector<glm::vec3> unpadded_texels(const std::vector<float>& v) {
  std::vector<glm::vec3> out(v.size() / 4);
  for (size_t k = 0; k < out.size(); ++k) out[k] = glm::vec3(v[4 * k], v[4 * k + 1], v[4 * k + 2]);
  return out;
}

struct ScreenSpaceFrameDevice::Impl {
  vk::Context& vk;
  int width = 0, height = 0;
  float focal = 1.0f;
  Camera camera;
  ScreenSpaceFrame embree_frame;  // gbuffer=embree
  std::unique_ptr<vk::RasterGBuffer> raster;
  vk::DeviceGBuffer gbuffer;  // gbuffer=raster
  vk::Image2D depth, normal;  // depth: gbuffer=embree only (raster: gbuffer.depth)
  std::unique_ptr<vk::ComputePipeline> eye_normals;
  VkDescriptorSet eye_set = VK_NULL_HANDLE;

  Impl(vk::Context& context, int w, int h, float f) : vk(context), width(w), height(h), focal(f) {
    normal = vk::Image2D(vk, w, h, VK_FORMAT_R32G32B32A32_SFLOAT);
  }
};

ScreenSpaceFrameDevice::ScreenSpaceFrameDevice(vk::Context& vk, const ScreenSpaceFrame& frame)
    : impl_(std::make_unique<Impl>(vk, frame.width, frame.height, frame.focal)) {
  impl_->embree_frame = frame;
  impl_->depth = vk::Image2D(vk, frame.width, frame.height, VK_FORMAT_R32_SFLOAT);
  impl_->depth.upload(frame.depth);
  impl_->normal.upload(padded_texels(frame.normal));
}

ScreenSpaceFrameDevice::ScreenSpaceFrameDevice(vk::Context& vk, const Scene& scene,
                                               const Camera& camera)
    : impl_(std::make_unique<Impl>(
          vk, camera.width, camera.height,
          static_cast<float>(camera.height) / (2.0f * camera.tan_half_fov_y))) {
  Impl& m = *impl_;
  m.camera = camera;
  m.raster = std::make_unique<vk::RasterGBuffer>(vk, scene);
  m.gbuffer = vk::make_device_gbuffer(vk, camera.width, camera.height);
  m.eye_normals = std::make_unique<vk::ComputePipeline>(
      vk, "eye normals", eye_normals_comp_spv,
      std::vector<VkDescriptorType>{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      sizeof(EyeNormalsPush));
  m.eye_set = m.eye_normals->make_set({m.gbuffer.normal, m.normal});
}

ScreenSpaceFrameDevice::~ScreenSpaceFrameDevice() = default;

int ScreenSpaceFrameDevice::width() const {
  return impl_->width;
}
int ScreenSpaceFrameDevice::height() const {
  return impl_->height;
}
float ScreenSpaceFrameDevice::focal() const {
  return impl_->focal;
}
const vk::Image2D& ScreenSpaceFrameDevice::depth() const {
  return impl_->raster ? impl_->gbuffer.depth : impl_->depth;
}
const vk::Image2D& ScreenSpaceFrameDevice::normal() const {
  return impl_->normal;
}

void ScreenSpaceFrameDevice::record(VkCommandBuffer cmd, vk::PassTimer& timer) {
  Impl& m = *impl_;
  if (!m.raster) return;
  m.raster->record(cmd, m.camera, m.gbuffer, &timer);  // timed as "geometry" by record()
  const EyeNormalsPush push{glm::vec4(m.camera.right, 0.0f), glm::vec4(m.camera.up, 0.0f),
                            glm::vec4(m.camera.forward, 0.0f), m.width, m.height};
  timer.begin(cmd, "geometry");
  m.eye_normals->dispatch(cmd, m.eye_set, push,
                          vk::group_count(static_cast<uint32_t>(m.width), kEyeNormalsGroup),
                          vk::group_count(static_cast<uint32_t>(m.height), kEyeNormalsGroup));
  timer.end(cmd);
  vk::pass_barrier(cmd);
}

ScreenSpaceFrame ScreenSpaceFrameDevice::download() const {
  const Impl& m = *impl_;
  if (!m.raster) return m.embree_frame;
  ScreenSpaceFrame f;
  f.width = m.width;
  f.height = m.height;
  f.focal = m.focal;
  f.depth = m.gbuffer.depth.download<float>();
  f.normal = unpadded_texels(m.normal.download<float>());
  return f;
}

void check_frame_matches_camera(const ScreenSpaceFrame& frame, const Camera& camera) {
  if (frame.width != camera.width || frame.height != camera.height)
    throw InputError("frame of " + std::to_string(frame.width) + "x" +
                     std::to_string(frame.height) + " pixels for a camera of " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
}

ParamSpec frame_source_param(const std::string& geometry_pass) {
  const std::string timed_as =
      geometry_pass.empty() ? "timed as geometry_ms" : "timed as geometry_ms, " + geometry_pass;
  return choice_param(
      {.name = "gbuffer",
       .def = "raster",
       .choices = {"raster", "embree"},
       .meaning = "raster: the scene rasterised on the device every frame (" + timed_as +
                  "); embree: the shared Embree G-buffer, uploaded once in prepare() (no "
                  "geometry_ms)"});
}

bool rasterises_frame(const ParamSet& params) {
  return params.choice("gbuffer") == "raster";
}

}  // namespace aoeval
