// What the hbao-split compute passes share: the bindings (one layout for the horizon, normal and
// blur passes), the kernel's accessors over them, and the kernel itself (hbao_kernel.glsl, the same
// source the CPU twin compiles as C++).
#define GLSL_OUT(T) out T
#define GLSL_INOUT(T) inout T
#define HBAO_IMAGES_PARAM
#define HBAO_IMAGES_ARG

#include "hbao_constants.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;    // linear depth, 0 = none
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D normal_image;  // eye-space normal
layout(std430, set = 0, binding = 2) readonly buffer RandomTexture { vec4 random_texels[]; };
layout(std430, set = 0, binding = 3) readonly buffer Directions { vec2 directions[]; };
layout(std430, set = 0, binding = 4) buffer Horizons { float horizons[]; };  // Nd planes
layout(set = 0, binding = 5, r32f) uniform image2D ot_image;       // O_T, pass 1 -> pass 2
layout(set = 0, binding = 6, r32f) uniform image2D raw_ao_image;   // A before the blur
layout(set = 0, binding = 7, r32f) uniform writeonly image2D ao_image;  // A after the blur

layout(push_constant) uniform Push {
  HbaoConstants c;
} pc;

// The pixel of this invocation. Lavapipe cuts a dispatch into as many contiguous runs of
// workgroups (in dispatch order, x fastest) as it has threads and gives each thread one run
// (lp_cs_tpool_queue_task), so with workgroups in image order the thread whose rows hold the model
// works while the one whose rows hold the sky waits: on bunny the second of two cores added only
// 22 % to the horizon pass. Dispatch row r therefore covers tile row (r * row_stride) mod rows,
// a stride near rows times the golden ratio and coprime with rows (workgroup_row_stride), so any
// contiguous run of dispatch rows covers tile rows spread over the whole image. A GPU's scheduler
// does not care about the order.
ivec2 hbao_invocation_pixel() {
  uint rows = gl_NumWorkGroups.y;
  uint row = (gl_WorkGroupID.y * uint(pc.c.row_stride)) % rows;
  return ivec2(gl_GlobalInvocationID.x, row * gl_WorkGroupSize.y + gl_LocalInvocationID.y);
}

int hbao_texel(float u, int size) {
  return clamp(int(u), 0, size - 1);  // int() beyond int's range: some int, clamped too
}
float hbao_depth(int i, int j) {
  return imageLoad(depth_image, ivec2(i, j)).r;
}
vec3 hbao_normal(int i, int j) {
  return imageLoad(normal_image, ivec2(i, j)).xyz;
}
vec3 hbao_random(int i, int j) {
  return random_texels[(j % pc.c.tile) * pc.c.tile + (i % pc.c.tile)].xyz;
}
vec2 hbao_direction(int d) {
  return directions[d];
}
float hbao_raw_ao(int i, int j) {
  return imageLoad(raw_ao_image, ivec2(i, j)).r;
}
int hbao_horizon_index(int i, int j, int d) {
  return (d * pc.c.height + j) * pc.c.width + i;
}
void hbao_store_horizon(int i, int j, int d, float h) {
  horizons[hbao_horizon_index(i, j, d)] = h;
}
float hbao_load_horizon(int i, int j, int d) {
  return horizons[hbao_horizon_index(i, j, d)];
}

#include "hbao_kernel.glsl"
