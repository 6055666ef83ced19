// The screen-space geometry pass with gbuffer=raster (ScreenSpaceFrameDevice, frame_device.h;
// hbao-split and gtao): the raster G-buffer's world-space normals in eye space (eye_normal.glsl,
// the conversion the CPU twins apply to the Embree ones).
#version 450
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba32f) uniform readonly image2D world_normal_image;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D eye_normal_image;

layout(push_constant) uniform Push {
  vec4 right;
  vec4 up;
  vec4 forward;
  ivec2 size;
} pc;

#include "eye_normal.glsl"

void main() {
  ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
  if (xy.x >= pc.size.x || xy.y >= pc.size.y) return;
  vec3 n = imageLoad(world_normal_image, xy).xyz;
  vec3 e = eye_normal(n, pc.right.xyz, pc.up.xyz, pc.forward.xyz);
  imageStore(eye_normal_image, xy, vec4(e, 0.0f));
}
