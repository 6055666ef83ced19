// The screen-space frame, the input of the estimators that work on depth and normals in eye space
// (hbao-split, gtao, raymarch-ssao; both twins of each): linear depth and eye-space normals made
// from the Embree G-buffer on the host (here) or by the raster pass on the device
// (frame_device.h), the seed rule's frame index, and the workgroup row order the compute passes
// share.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

// The inputs of the kernels in eye space (x right, y up, z forward), prepared on the host: linear
// depth (0 = background) and unit eye-space shading normals, row-major, row 0 at the top.
struct ScreenSpaceFrame {
  int width = 0;
  int height = 0;
  float focal = 1.0f;  // pixels: height / (2 tan(fov_y / 2))
  std::vector<float> depth;
  std::vector<glm::vec3> normal;
  // The principal point is (width / 2, height / 2) + centre_shift pixels: 0 for a frame drawn by a
  // camera, a quarter pixel for a half-resolution frame of one (half_res.h).
  glm::vec2 centre_shift{0.0f};
};
// The Embree G-buffer's depth and normals, the normals turned to eye space by eye_normal.glsl
// (the raster route's conversion, eye_normals.comp); uncovered pixels get depth 0, normal
// (0, 0, -1).
ScreenSpaceFrame screen_space_frame_from_gbuffer(const GBuffer& gbuffer);
// A frame's size and focal length for `camera`, without pixels (what the raster pass will draw).
ScreenSpaceFrame screen_space_frame_shape(const Camera& camera);

// The seed rule's k of the frame a context is (CONTRACT §10): FrameInfo::seed_offset, 0 for a still
// view. hbao-split and gtao keep state over a sequence (EstimatorInfo::keeps_state) and draw frame
// k's noise from it themselves (HbaoSettings::frame, GtaoSettings::frame).
inline uint64_t noise_frame(const EstimateContext& context) {
  return context.frame ? context.frame->seed_offset : 0;
}

// A stride coprime with `rows` (tile rows of a compute pass's workgroup side) near rows times the
// golden ratio: dispatch row r covers tile row (r * stride) mod rows (hbao_common.glsl says why;
// hbao-split's and gtao's passes both dispatch in this order).
int workgroup_row_stride(int rows);

}  // namespace aoeval
