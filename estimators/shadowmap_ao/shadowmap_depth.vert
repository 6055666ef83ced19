// shadowmap-ao, depth pass, vertex stage: one light's orthographic projection (shadowmap_common.glsl)
// into its tile of the atlas (the viewport). Drawn non-indexed through the index buffer, as the raster
// G-buffer does.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_common.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = 2) readonly buffer Indices { uint indices[]; };

layout(push_constant) uniform Push {
  vec4 centre_radius;
  uint light;
} pc;

void main() {
  const uint i = indices[gl_VertexIndex];
  const vec3 p = vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
  gl_Position = vec4(light_space(p, pc.centre_radius, lights[pc.light]), 1.0);
}
