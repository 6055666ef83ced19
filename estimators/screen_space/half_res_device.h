// Half resolution on the Vulkan device (hbao-split, gtao): the half-resolution G-buffer made from
// a ScreenSpaceFrameDevice by a downsample pass, and the joint bilateral upsample pass back to full
// resolution, both timed (downsample_ms, upsample_ms). The algorithm is half_res.glsl's.
#pragma once

#include <vulkan/vulkan.h>

#include <memory>

#include "estimators/screen_space/frame_device.h"
#include "estimators/screen_space/half_res.h"

namespace aoeval {

class HalfResDevice {
 public:
  // `full` must outlive this. `vector`: the upsample also carries a vector image (bent normals).
  HalfResDevice(vk::Context& vk, const ScreenSpaceFrameDevice& full, bool vector);
  ~HalfResDevice();
  HalfResDevice(const HalfResDevice&) = delete;
  HalfResDevice& operator=(const HalfResDevice&) = delete;

  // The half-resolution frame's size, focal length and principal point (half_resolution_shape).
  const ScreenSpaceFrame& shape() const;
  // The half-resolution G-buffer the technique's passes read.
  const vk::Image2D& depth() const;
  const vk::Image2D& normal() const;
  // What the upsample writes at full resolution: AO (r32f) and the vector (rgba32f, w = 0).
  const vk::Image2D& ao() const;
  const vk::Image2D& vector() const;
  // The half-resolution images the upsample reads; call once before the first record_upsample.
  void bind(const vk::Image2D& low_ao, const vk::Image2D* low_vector);
  void record_downsample(VkCommandBuffer cmd, vk::PassTimer& timer);
  void record_upsample(VkCommandBuffer cmd, vk::PassTimer& timer);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aoeval
