// The screen-space frame on the Vulkan device, shared by hbao-split and gtao: eye-space depth and
// normals, either uploaded once from the Embree G-buffer (gbuffer=embree) or drawn every frame by
// the raster G-buffer pass with its normals turned to eye space (gbuffer=raster), so that both
// estimators feed their passes the same images the same way.
#pragma once

#include <vulkan/vulkan.h>

#include <memory>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/screen_space/frame.h"
#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_resources.h"
#include "scenes/camera.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval {

class ScreenSpaceFrameDevice {
 public:
  // gbuffer=embree: `frame` uploaded once (its size and focal checked by the caller).
  ScreenSpaceFrameDevice(vk::Context& vk, const ScreenSpaceFrame& frame);
  // gbuffer=raster: `scene` rasterised from `camera` by record().
  ScreenSpaceFrameDevice(vk::Context& vk, const Scene& scene, const Camera& camera);
  ~ScreenSpaceFrameDevice();
  ScreenSpaceFrameDevice(const ScreenSpaceFrameDevice&) = delete;
  ScreenSpaceFrameDevice& operator=(const ScreenSpaceFrameDevice&) = delete;

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
  ScreenSpaceFrame download() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// InputError unless `frame` has `camera`'s size (an uploaded frame drawn through another camera).
void check_frame_matches_camera(const ScreenSpaceFrame& frame, const Camera& camera);

// The device of a technique on a ScreenSpaceFrameDevice (HbaoDevice, GtaoDevice) for one view: with
// gbuffer=raster, Device(vk, settings, scene, camera) rasterises the scene at every frame; with
// gbuffer=embree, Device(vk, settings, frame, camera) uploads the shared Embree G-buffer once.
template <class Device, class Settings>
std::unique_ptr<Device> make_frame_device(vk::Context& vk, const Settings& settings, bool raster,
                                          const Scene& scene, const GBuffer& gbuffer) {
  if (raster) return std::make_unique<Device>(vk, settings, scene, gbuffer.camera);
  return std::make_unique<Device>(vk, settings, screen_space_frame_from_gbuffer(gbuffer),
                                  gbuffer.camera);
}

// The Estimator of such a technique (hbao-split, gtao): prepare() builds the device on the shared
// Vulkan context with the noise of the context's frame (Settings::frame), run() runs one frame and
// turns it into an EstimateResult with `result_of`; derived() is frame_derived() of the settings
// (hbao_split.h, gtao.h): what a still view's row records about the technique's time design.
template <class Device, class Settings>
class FrameDeviceEstimator : public Estimator {
 public:
  using ResultOf = EstimateResult (*)(const Settings&, Device&);
  FrameDeviceEstimator(const Settings& settings, bool raster, ResultOf result_of)
      : settings_(settings), raster_(raster), result_of_(result_of) {}
  void prepare(const EstimateContext& context) override {
    settings_.frame = noise_frame(context);
    still_ = context.frame == nullptr;
    device_ = make_frame_device<Device>(vk::require_shared_context(), settings_, raster_,
                                        context.scene, context.gbuffer);
  }
  EstimateResult run(const EstimateContext& context) override {
    if (!device_) prepare(context);
    return result_of_(settings_, *device_);
  }
  nlohmann::json derived() const override { return frame_derived(settings_, still_); }

 private:
  Settings settings_;
  bool raster_;
  ResultOf result_of_;
  std::unique_ptr<Device> device_;
  bool still_ = true;
};

// The `gbuffer` parameter of the estimators that run on a ScreenSpaceFrameDevice (hbao-split,
// gtao): where their frame comes from, "raster" (the default) or "embree". `geometry_pass` names
// what the estimator's paper calls the raster pass, if anything ("" for nothing).
ParamSpec frame_source_param(const std::string& geometry_pass);
// Whether a ParamSet of such an estimator chose gbuffer=raster.
bool rasterises_frame(const ParamSet& params);

// RGBA texels (w = 0) of vec3s, and back: the layout of the normal images.
std::vector<glm::vec4> padded_texels(const std::vector<glm::vec3>& v);
std::vector<glm::vec3> unpadded_texels(const std::vector<float>& v);

}  // namespace aoeval
