// hbao-split on Vulkan: the kernel of hbao_kernel.glsl as three compute passes (horizon occlusion,
// normal occlusion, blur) after the geometry pass (the raster G-buffer of estimators/vulkan, or an
// upload of the Embree G-buffer done once, outside the frame), with a GPU timestamp around each.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "estimators/hbao_split/hbao_split.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_resources.h"
#include "scenes/camera.h"
#include "scenes/scene.h"

namespace aoeval {

struct HbaoGpuResult {
  std::vector<float> ao;          // final AO (blurred when settings.blur), 0 where not covered
  std::vector<float> raw_ao;      // before the blur
  std::vector<float> horizon_ao;  // 1 - O_T where covered, else 0
  // GPU time per pass: geometry_ms (gbuffer=raster only: raster pass + normals to eye space),
  // horizon_ms, normal_ms, blur_ms (blur on only), downsample_ms and upsample_ms (resolution =
  // half), total_ms (first to last timestamp).
  std::map<std::string, double> pass_ms;
};

class HbaoDevice {
 public:
  // gbuffer=embree: `frame` (from the shared Embree G-buffer, seen through `camera`: its size is
  // checked) is uploaded here, once.
  HbaoDevice(vk::Context& vk, const HbaoSettings& settings, const ScreenSpaceFrame& frame,
             const Camera& camera);
  // gbuffer=raster: the scene is rasterised through `camera` at every run().
  HbaoDevice(vk::Context& vk, const HbaoSettings& settings, const Scene& scene,
             const Camera& camera);
  ~HbaoDevice();
  HbaoDevice(const HbaoDevice&) = delete;
  HbaoDevice& operator=(const HbaoDevice&) = delete;

  // One frame: records and submits the passes, waits, reads the timestamps and downloads.
  HbaoGpuResult run();
  // The depth image the passes read (the bench's bare-fetch loop reads the same one).
  const vk::Image2D& depth_image() const;
  // The G-buffer the passes saw, for the CPU twin (gbuffer=raster: downloaded after a run()).
  ScreenSpaceFrame frame() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The bench's baseline (aoeval bench hbao): a shader that only fetches, `walks` x `steps` nearest
// texel imageLoads per pixel of `depth` along screen-space walks of `step_px` pixels per step (the
// access pattern of the horizon and normal rays), summed and stored so that nothing is optimised
// away. Built once; run_ms() dispatches it and returns its GPU time, so that the bench can
// alternate it with hbao-split's passes and both see the same load on a shared machine.
class BareFetch {
 public:
  BareFetch(vk::Context& vk, const vk::Image2D& depth, int walks, int steps, float step_px);
  ~BareFetch();
  double run_ms();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

EstimatorInfo hbao_split_estimator();

}  // namespace aoeval
