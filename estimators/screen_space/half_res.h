// Half resolution for the screen-space estimators on ScreenSpaceFrame (hbao-split, gtao; both
// twins): the `resolution` parameter, the half-resolution frame (pixel (i, j) = full pixel (2i,
// 2j)) and the joint bilateral upsample back to full resolution. The weights and the choice of
// samples are documented, once, in half_res.glsl, which the CPU compiles here and the shaders on
// the device.
#pragma once

#include <glm/vec3.hpp>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/screen_space/frame.h"

namespace aoeval {
namespace half_res_glsl {
#include "estimators/screen_space/half_res_constants.glsl"
}  // namespace half_res_glsl
using half_res_glsl::HalfResConstants;

// The `resolution` parameter of hbao-split and gtao (both twins): "full" (the default) or "half"
// (the AO computed on the half-resolution frame, then upsampled).
ParamSpec resolution_param();
bool half_resolution(const ParamSet& params);

// The half-resolution frame of `full`: ceil(W / 2) x ceil(H / 2) pixels, focal f / 2, and the
// principal point where full pixel (2i, 2j)'s centre falls: full centre u = 2i + 1/2 must be half
// centre i + 1/2 seen through (u - W/2) / f = (i + 1/2 - c') / (f / 2), so c' = W/4 + 1/4, i.e.
// centre_shift = W/4 + 1/4 - ceil(W/2)/2 (1/4 for even W, 0 for odd), and the same in y.
// The shape has no pixels; the frame copies depth and normal of every (2i, 2j).
ScreenSpaceFrame half_resolution_shape(const ScreenSpaceFrame& full);
ScreenSpaceFrame half_resolution_frame(const ScreenSpaceFrame& full);
HalfResConstants half_res_constants(const ScreenSpaceFrame& full, bool vector);

// The joint bilateral upsample (half_res.glsl) of a half-resolution image of `full`'s half frame
// to full resolution: scalars (AO: 1 where no sample is usable) and vectors (0 there).
std::vector<float> upsample_half_res(const ScreenSpaceFrame& full, const std::vector<float>& low);
std::vector<glm::vec3> upsample_half_res(const ScreenSpaceFrame& full,
                                         const std::vector<glm::vec3>& low);

}  // namespace aoeval
