// The screen-space frame on the Vulkan device, shared by hbao-split and gtao: eye-space depth and
// normals, either uploaded once from the Embree G-buffer (gbuffer=embree) or drawn every frame by
// the raster G-buffer pass with its normals turned to eye space (gbuffer=raster), so that both
// estimators feed their passes the same images the same way.
#pragma once

#include <vulkan/vulkan.h>

#include <memory>
#include <vector>

#include "camera.h"
#include "estimators/estimator.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_resources.h"
#include "scene.h"

namespace aoeval {

class HbaoFrameDevice {
 public:
  // gbuffer=embree: `frame` uploaded once (its size and focal checked by the caller).
  HbaoFrameDevice(vk::Context& vk, const HbaoFrame& frame);
  // gbuffer=raster: `scene` rasterised from `camera` by record().
  HbaoFrameDevice(vk::Context& vk, const Scene& scene, const Camera& camera);
  ~HbaoFrameDevice();
  HbaoFrameDevice(const HbaoFrameDevice&) = delete;
  HbaoFrameDevice& operator=(const HbaoFrameDevice&) = delete;

  int width() const;
  int height() const;
  float focal() const;  // pixels: height / (2 tan(fov_y / 2))
  // What the passes read: linear eye depth (0 = not covered) and eye-space normals (RGBA, w = 0).
  const vk::Image2D& depth() const;
  const vk::Image2D& normal() const;
  // gbuffer=raster: records the raster pass and the eye-normal conversion, both timed as
  // "geometry" (the spans add up), then a barrier. gbuffer=embree: records nothing.
  void record(VkCommandBuffer cmd, vk::PassTimer& timer);
  // The frame the passes saw (downloaded with gbuffer=raster).
  HbaoFrame download() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The `gbuffer` parameter of the estimators that run on an HbaoFrameDevice (hbao-split, gtao):
// where their frame comes from, "raster" (the default) or "embree". `geometry_pass` names what
// the estimator's paper calls the raster pass, if anything ("" for nothing).
ParamSpec frame_source_param(const std::string& geometry_pass);
// Whether a ParamSet of such an estimator chose gbuffer=raster.
bool rasterises_frame(const ParamSet& params);

// RGBA texels (w = 0) of vec3s, and back: the layout of the normal images.
std::vector<glm::vec4> padded_texels(const std::vector<glm::vec3>& v);
std::vector<glm::vec3> unpadded_texels(const std::vector<float>& v);

}  // namespace aoeval
