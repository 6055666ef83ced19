// Half resolution, pass 1: the half-resolution G-buffer, pixel (i, j) = full pixel (2i, 2j)
// (half_res.glsl says why this sample).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "half_res_constants.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D full_depth;
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D full_normal;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D low_depth;
layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D low_normal;
layout(push_constant) uniform Push {
  HalfResConstants c;
} pc;

void main() {
  ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
  if (xy.x >= pc.c.low_width || xy.y >= pc.c.low_height) return;
  imageStore(low_depth, xy, imageLoad(full_depth, 2 * xy));
  imageStore(low_normal, xy, imageLoad(full_normal, 2 * xy));
}
