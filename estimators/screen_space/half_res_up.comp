// Half resolution, last pass: the joint bilateral upsample of the half-resolution AO (and, for
// gtao, the bent normals) to full resolution, with half_res.glsl's weights: the same text and the
// same order of operations as the CPU twins' upsample_half_res (half_res.cpp).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "half_res_constants.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;      // full resolution
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D normal_image;  // full, eye space
layout(set = 0, binding = 2, r32f) uniform readonly image2D low_scalar;       // half resolution
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D low_vector;    // half (vector = 1)
layout(set = 0, binding = 4, r32f) uniform writeonly image2D scalar_out;
layout(set = 0, binding = 5, rgba32f) uniform writeonly image2D vector_out;
layout(push_constant) uniform Push {
  HalfResConstants c;
} pc;

#define HALFRES_IMAGES_PARAM
#define HALFRES_IMAGES_ARG
float halfres_depth(int i, int j) {
  return imageLoad(depth_image, ivec2(i, j)).r;
}
vec3 halfres_normal(int i, int j) {
  return imageLoad(normal_image, ivec2(i, j)).xyz;
}
#include "half_res.glsl"

void main() {
  ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  precise float scalar = 0.0f;
  precise vec3 vector = vec3(0.0f);
  if (halfres_depth(xy.x, xy.y) > 0.0f) {
    vec4 w = halfres_weights(xy.x, xy.y, pc.c);
    if (!(w.x > 0.0f || w.y > 0.0f || w.z > 0.0f || w.w > 0.0f)) {
      scalar = 1.0f;  // no usable sample: nothing seen around the pixel occludes it
    } else {
      for (int k = 0; k < 4; ++k) {
        ivec2 s = halfres_candidate(xy.x, xy.y, k, pc.c);
        scalar += imageLoad(low_scalar, s).r * w[k];
        if (pc.c.vector != 0) vector += imageLoad(low_vector, s).xyz * w[k];
      }
    }
  }
  imageStore(scalar_out, xy, vec4(scalar));
  if (pc.c.vector != 0) imageStore(vector_out, xy, vec4(vector, 0.0f));
}
