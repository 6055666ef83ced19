#version 450
// history-ssao: a deliberately noisy screen-space AO (few samples per pixel, a pattern that changes
// every frame) made smooth over time by the ABI's temporal bindings (aoeval estimators abi):
//   new_k  = 1 - (occluded samples) / s, from s points in the normal's hemisphere around P;
//            occluded: behind the visible surface (depth and its tangent plane), within R;
//   AO_k   = mix(new_k, aoeval_history at p - aoeval_motion, w)   where the point was visible,
//   AO_k   = new_k                                                at frame 0 and where disoccluded.
// An exponential average of independent frames with weight w keeps (1 - w) / (1 + w) of their
// variance and a frame-to-frame difference variance of 2 (1 - w)^2 / (1 + w) of it (AR(1) with
// coefficient w): at w = 0.8 about 1/45, so temporal_rmse falls by about 6.7x on a static camera,
// where motion is 0 and the reprojection reads the same pixel. A moving view ghosts where the
// nearest-pixel reprojection lands on a different surface than it should (no neighbourhood clamp).
layout(local_size_x = 8, local_size_y = 8) in;

const float kGolden = 0.61803399;   // 1 / phi: a low-discrepancy second coordinate
const float kPlastic = 0.75487767;  // 1 / plastic number: a third one

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!aoeval_inside(p)) return;
  if (!aoeval_covered(p)) {
    imageStore(aoeval_out, p, vec4(0.0));
    return;
  }
  const vec3 P = imageLoad(aoeval_position, p).xyz;
  const vec3 N = imageLoad(aoeval_normal, p).xyz;
  // The pixel's noise: a new tile every frame (seed + k), so each frame's estimate is independent.
  const vec4 noise = imageLoad(aoeval_noise, p % aoeval.pass.w);
  const vec3 T = normalize(cross(N, abs(N.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
  const vec3 B = cross(N, T);
  const int s = aoeval.params.samples;
  const float R = aoeval.params.radius;
  float occluded = 0.0;
  for (int i = 0; i < s; ++i) {
    // A rank-1 lattice in [0, 1)^3 shifted by the pixel's noise (Cranley-Patterson rotation).
    const vec3 u = fract(vec3((float(i) + 0.5) / float(s), float(i) * kGolden,
                              float(i) * kPlastic) + noise.xyz);
    // A cosine-distributed direction (Malley's method) at a distance in (0.1 R, R].
    const float r = sqrt(u.x), phi = 6.28318531 * u.y;
    const vec3 d = r * cos(phi) * T + r * sin(phi) * B + sqrt(max(0.0, 1.0 - u.x)) * N;
    const vec3 S = P + R * mix(0.1, 1.0, u.z) * d;
    if (S.z >= 0.0) continue;  // behind the camera
    const ivec2 q = ivec2(floor(aoeval_project(S)));
    if (!aoeval_covered(q)) continue;  // the background never occludes
    // Occluded: the visible surface at q is in front of S in depth, within range, and S lies
    // behind that surface's tangent plane (which keeps a plane seen at a grazing angle from
    // occluding itself between pixel centres, where the depth at q's centre is not S's surface).
    const float gap = -S.z - imageLoad(aoeval_depth, q).r;
    const vec3 Q = imageLoad(aoeval_position, q).xyz, Nq = imageLoad(aoeval_normal, q).xyz;
    if (gap > aoeval.params.bias && gap < R && dot(S - Q, Nq) < 0.0) occluded += 1.0;
  }
  float ao = 1.0 - occluded / float(s);
  const float w = aoeval.params.history;
  if (aoeval.frame > 0 && w > 0.0 && imageLoad(aoeval_disoccluded, p).r < 0.5) {
    // Where this pixel's point was in the previous frame: its centre minus the motion.
    const ivec2 h = ivec2(floor(vec2(p) + 0.5 - imageLoad(aoeval_motion, p).xy));
    if (aoeval_inside(h)) ao = mix(ao, imageLoad(aoeval_history, h).r, w);
  }
  imageStore(aoeval_out, p, vec4(ao));
}
