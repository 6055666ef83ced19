// gtao on Vulkan: the kernel of gtao_kernel.glsl as two compute passes (horizons and integrals,
// denoise) after the geometry pass (the raster G-buffer of estimators/vulkan, or an upload of the
// Embree G-buffer done once, outside the frame), with a GPU timestamp around each.
#pragma once

#include <memory>

#include "estimators/gtao/gtao.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/camera.h"
#include "scenes/scene.h"

namespace aoeval {

class GtaoDevice {
 public:
  // gbuffer=embree: `frame` (from the shared Embree G-buffer) is uploaded here, once.
  GtaoDevice(vk::Context& vk, const GtaoSettings& settings, const ScreenSpaceFrame& frame,
             const Camera& camera);
  // gbuffer=raster: the scene is rasterised through `camera` at every run().
  GtaoDevice(vk::Context& vk, const GtaoSettings& settings, const Scene& scene,
             const Camera& camera);
  ~GtaoDevice();
  GtaoDevice(const GtaoDevice&) = delete;
  GtaoDevice& operator=(const GtaoDevice&) = delete;

  // One frame: records and submits the passes, waits, reads the timestamps (geometry_ms with
  // gbuffer=raster, downsample_ms and upsample_ms at half resolution, horizon_ms, denoise_ms when
  // on, total_ms) and downloads.
  GtaoOutput run();
  // The G-buffer the passes saw, for the CPU twin (gbuffer=raster: downloaded after a run()).
  ScreenSpaceFrame frame() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aoeval
