// What the gtao compute passes share: the bindings (one layout for both passes), the kernel's
// accessors over them, and the kernel itself (gtao_kernel.glsl, the same source the CPU twin
// compiles as C++).
#define GLSL_OUT(T) out T
#define GTAO_IMAGES_PARAM
#define GTAO_IMAGES_ARG

#include "gtao_constants.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;      // 0 = background
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D normal_image;  // eye-space normal
layout(std430, set = 0, binding = 2) readonly buffer Rotation { vec2 rotation[]; };
layout(std430, set = 0, binding = 3) readonly buffer Steps { float step_table[]; };
layout(std430, set = 0, binding = 4) readonly buffer Slices { vec2 slice_table[]; };
layout(set = 0, binding = 5, r32f) uniform image2D raw_ao_image;      // pass 1 -> pass 2
layout(set = 0, binding = 6, rgba32f) uniform image2D raw_bent_image;  // pass 1 -> pass 2
layout(set = 0, binding = 7, r32f) uniform writeonly image2D ao_image;
layout(set = 0, binding = 8, rgba32f) uniform writeonly image2D bent_image;

layout(push_constant) uniform Push {
  GtaoConstants c;
} pc;

// The pixel of this invocation, workgroup rows in hbao-split's order (hbao_common.glsl says why:
// lavapipe gives each thread a contiguous run of workgroups).
ivec2 gtao_invocation_pixel() {
  uint rows = gl_NumWorkGroups.y;
  uint row = (gl_WorkGroupID.y * uint(pc.c.row_stride)) % rows;
  return ivec2(gl_GlobalInvocationID.x, row * gl_WorkGroupSize.y + gl_LocalInvocationID.y);
}

// The same as the C++ twin's (gtao_cpu_kernel.h): out-of-range and NaN give a far-off texel.
int gtao_floor(float u) {
  if (!(u > -1.0e6f && u < 1.0e6f)) return -1000000;
  return int(floor(u));
}
float gtao_depth(int i, int j) {
  return imageLoad(depth_image, ivec2(i, j)).r;
}
vec3 gtao_normal(int i, int j) {
  return imageLoad(normal_image, ivec2(i, j)).xyz;
}
int gtao_texel(int i, int j) {
  return (j % pc.c.tile) * pc.c.tile + (i % pc.c.tile);
}
vec2 gtao_rotation(int i, int j) {
  return rotation[gtao_texel(i, j)];
}
float gtao_step(int i, int j, int k) {
  return step_table[gtao_texel(i, j) * pc.c.steps + k];
}
vec2 gtao_slice(int s) {
  return slice_table[s];
}
float gtao_raw_ao(int i, int j) {
  return imageLoad(raw_ao_image, ivec2(i, j)).r;
}
vec3 gtao_raw_bent(int i, int j) {
  return imageLoad(raw_bent_image, ivec2(i, j)).xyz;
}

#include "gtao_kernel.glsl"
