#version 450
// Scalable Ambient Obscurance (McGuire, Mara, Luebke, HPG 2012), the obscurance pass, on aoeval's
// GLSL plug-in ABI (aoeval estimators abi). Without the paper's depth MIP chain: every tap reads
// the full-resolution position buffer, as the paper's baseline does.
//
// Taps: s points on a spiral around the pixel, tap i at screen radius h_i = alpha_i * R' with
// alpha_i = (i + 0.5) / s and angle theta_i = 2 pi alpha_i tau + phi, where R' is the world radius
// r projected at the pixel's depth and phi a per-pixel rotation (the paper's hash of the pixel
// coordinates, (3 x ^ y + x y) * 10). Estimator: Alchemy's with the falloff f(v) = (r^2 - v.v)^3,
// which is 0 beyond r and needs no division by r per tap:
//   A = max(0, 1 - (5 sigma / (r^6 s)) sum_i max(0, r^2 - v_i.v_i)^3 max(0, (v_i.n - beta) / (v_i.v_i + eps)))
// An open plane gives v_i . n = 0, so A = 1.
layout(local_size_x = 8, local_size_y = 8) in;

const float kEpsilon = 0.01;  // the paper's epsilon (in squared scene units, as its code)

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!aoeval_inside(p)) return;
  if (!aoeval_covered(p)) {
    imageStore(aoeval_out, p, vec4(0.0));
    return;
  }
  const vec3 c = imageLoad(aoeval_position, p).xyz;
  const vec3 n = imageLoad(aoeval_normal, p).xyz;
  const float r = aoeval.params.radius, r2 = r * r;
  const int s = aoeval.params.samples;
  const float disk_px = r * aoeval.lens.x / -c.z;
  const float phi = float(3 * p.x ^ p.y + p.x * p.y) * 10.0;  // the paper code's hash, as written
  float sum = 0.0;
  for (int i = 0; i < s; ++i) {
    const float alpha = (float(i) + 0.5) / float(s);
    const float theta = alpha * (float(aoeval.params.turns) * 6.28318530718) + phi;
    const ivec2 q = ivec2(floor(vec2(p) + 0.5 + alpha * disk_px * vec2(cos(theta), sin(theta))));
    if (!aoeval_covered(q)) continue;
    const vec3 v = imageLoad(aoeval_position, q).xyz - c;
    const float vv = dot(v, v), vn = dot(v, n);
    const float f = max(r2 - vv, 0.0);
    sum += f * f * f * max((vn - aoeval.params.bias) / (kEpsilon + vv), 0.0);
  }
  const float r6 = r2 * r2 * r2;
  imageStore(aoeval_out, p, vec4(max(0.0, 1.0 - sum * aoeval.params.intensity / r6 * (5.0 / float(s)))));
}
