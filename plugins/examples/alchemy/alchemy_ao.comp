#version 450
// Alchemy ambient obscurance (McGuire, Osman, Bukowski, Hennessy, HPG 2011), one compute pass on
// aoeval's GLSL plug-in ABI (aoeval estimators abi). For the point C of each pixel, with eye-space
// normal n, s points C_i are read back from the position buffer at screen positions on a disk
// whose radius is the projection of the world-space radius r; with v_i = C_i - C the paper's
// estimator is
//   A = max(0, 1 - (2 sigma / s) * sum_i max(0, v_i . n + z_C beta) / (v_i . v_i + epsilon))^k
// where z_C < 0 is C's eye-space z (so z_C beta is a depth-proportional bias) and epsilon keeps
// the quotient finite. The 1 / (v . v) falloff cancels the projected-area terms of the visibility
// integral the paper derives the estimator from. An open plane gives v_i . n = 0, so A = 1.
layout(local_size_x = 8, local_size_y = 8) in;

const float kEpsilon = 0.0001;  // the paper's epsilon

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!aoeval_inside(p)) return;
  if (!aoeval_covered(p)) {
    imageStore(aoeval_out, p, vec4(0.0));
    return;
  }
  const vec3 c = imageLoad(aoeval_position, p).xyz;
  const vec3 n = imageLoad(aoeval_normal, p).xyz;
  const int s = aoeval.params.samples;
  const float r = aoeval.params.radius;
  // The disk's radius in pixels: r projected at C's depth (focal length f in pixels).
  const float disk_px = r * aoeval.lens.x / -c.z;
  // Per-pixel rotation and radial offset of the pattern from the noise tile.
  const vec4 noise = imageLoad(aoeval_noise, p % aoeval.pass.w);
  float sum = 0.0;
  for (int i = 0; i < s; ++i) {
    // Stratified in angle, low-discrepancy in radius (golden ratio), area-uniform on the disk.
    const float angle = 6.28318530718 * (float(i) + noise.x) / float(s);
    const float radius = disk_px * sqrt(fract((float(i) + noise.y) * 0.61803398875));
    const ivec2 q = ivec2(floor(vec2(p) + 0.5 + radius * vec2(cos(angle), sin(angle))));
    if (!aoeval_covered(q)) continue;  // off screen or background: no occluder seen
    const vec3 v = imageLoad(aoeval_position, q).xyz - c;
    sum += max(0.0, dot(v, n) + c.z * aoeval.params.bias) / (dot(v, v) + kEpsilon);
  }
  const float a = max(0.0, 1.0 - 2.0 * aoeval.params.intensity / float(s) * sum);
  imageStore(aoeval_out, p, vec4(pow(a, aoeval.params.contrast)));
}
