// shadowmap-ao, accumulation pass (GPU Gems ch. 17 §17.3): each receiver tests itself against the
// lights of this pass (their maps side by side in the atlas) and adds, per side it has,
//   acc[2 s]     += (lit · l, w · lit)   and   acc[2 s + 1].x += w
// for every light l above that side (w = 1 or n·l), and in dome mode acc[2 s + 1].x += w' for the
// light's mirror image below the horizon when it is above the side (blocked by the assumed ground).
// Each invocation owns its receiver and adds lights in order: same bits on every run.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_common.glsl"

layout(local_size_x = 64) in;

// 1 = receivers from the buffer, two sides each (mode=vertex); 0 = G-buffer pixels (mode=pixel).
layout(constant_id = 0) const uint kVertexMode = 0;

layout(set = 0, binding = 0, r32f) uniform readonly image2D atlas;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D gb_position;  // w = coverage A
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D gb_normal;
layout(set = 0, binding = 4, rgba32f) uniform readonly image2D gb_geometric_normal;
// Per receiver: position (w = 1 when it has a surface), normal (face normal, or zero).
layout(std430, set = 0, binding = 5) readonly buffer Receivers { vec4 receivers[]; };
layout(std430, set = 0, binding = 6) buffer Accumulators { vec4 acc[]; };

layout(push_constant) uniform Push {
  vec4 centre_radius;
  uint first_light, light_count, resolution, receiver_count;
  uint width, cosine, dome, pad;
  float bias, slope_bias, max_tan, pad2;
} pc;

void main() {
  // Rows of work groups: a dispatch has at most 65535 groups per axis (millions of receivers).
  const uint r = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64;
  if (r >= pc.receiver_count) return;
  vec3 p, n, ng;
  if (kVertexMode == 1) {
    const vec4 pw = receivers[2 * r];
    if (pw.w == 0.0) return;
    p = pw.xyz;
    n = receivers[2 * r + 1].xyz;
    ng = n;
  } else {
    const ivec2 px = ivec2(r % pc.width, r / pc.width);
    const vec4 pw = imageLoad(gb_position, px);
    if (pw.w < 0.5) return;
    p = pw.xyz;
    n = imageLoad(gb_normal, px).xyz;
    ng = imageLoad(gb_geometric_normal, px).xyz;
  }
  const uint sides = kVertexMode == 1 ? 2 : 1;
  const float res = float(pc.resolution);
  vec4 lit_sum[2] = vec4[2](acc[4 * r], acc[4 * r + 2]);
  float total[2] = float[2](acc[4 * r + 1].x, acc[4 * r + 3].x);
  for (uint k = 0; k < pc.light_count; ++k) {
    const Light l = lights[pc.first_light + k];
    const vec3 d = l.d.xyz;
    const float cg = dot(ng, d);
    // The shadow test, shared by both sides: the receiver's map depth against the stored nearest
    // depth, less the receiver-side bias of bias + slope_bias · tan θ texels (l.d.w: this map's
    // texel in units of the sphere fit's, shadowmap_common.glsl).
    const vec3 q = light_space(p, pc.centre_radius, l);
    const ivec2 texel = clamp(ivec2(floor((q.xy * 0.5 + 0.5) * res)), ivec2(0),
                              ivec2(int(pc.resolution) - 1));
    // Point sampling at the texel centre, as shadow-map hardware compares (no filtering).
    const float stored = imageLoad(atlas, texel + ivec2(int(k * pc.resolution), 0)).x;
    const float ac = abs(cg);
    const float tan_theta = min(sqrt(max(0.0, 1.0 - ac * ac)) / max(ac, 1e-6), pc.max_tan);
    const float slack = (pc.bias + pc.slope_bias * tan_theta) * l.d.w / res;
    const float lit = q.z - slack <= stored ? 1.0 : 0.0;
    const vec3 mirror = vec3(d.x, -d.y, d.z);
    for (uint s = 0; s < sides; ++s) {
      const float sign_s = s == 0 ? 1.0 : -1.0;
      const vec3 ns = sign_s * n;
      const float c = dot(ns, d);
      if (c > 0.0 && sign_s * cg > 0.0) {
        const float w = pc.cosine == 1 ? c : 1.0;
        lit_sum[s] += vec4(lit * d, w * lit);
        total[s] += w;
      }
      if (pc.dome == 1) {
        const float cm = dot(ns, mirror);
        if (cm > 0.0 && sign_s * dot(ng, mirror) > 0.0) total[s] += pc.cosine == 1 ? cm : 1.0;
      }
    }
  }
  acc[4 * r] = lit_sum[0];
  acc[4 * r + 1].x = total[0];
  if (sides == 2) {
    acc[4 * r + 2] = lit_sum[1];
    acc[4 * r + 3].x = total[1];
  }
}
