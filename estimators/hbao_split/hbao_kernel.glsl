// Horizon-split ambient occlusion, per pixel: Dimitrov, Bavoil, Sainz 2008, "Horizon-Split Ambient
// Occlusion". ONE source for both twins: the Vulkan compute shaders include it as GLSL 4.50, the
// CPU twin (hbao_cpu.cpp) includes it as C++ through glsl_compat.h. So it uses only spellings both
// languages share (float literals with an f suffix, float()/int() casts, `precise` on every result
// that could be contracted into an fma, HBAO_OUT for out parameters) and the same operations in the
// same order, which is what makes the twins agree to 1e-3 (hbao_split_test.cpp). It needs
// hbao_basics.glsl (hbao_dot, hbao_eye_normal) included before it.
//
// Before including it, each side defines the accessors of the input images (nearest-texel reads,
// §4.1.1; coordinates are always inside the image):
//   float hbao_depth(HBAO_IMAGES_PARAM int i, int j)     linear view depth z > 0, 0 = background
//   vec3  hbao_normal(HBAO_IMAGES_PARAM int i, int j)    unit eye-space normal, facing the viewer
//   vec3  hbao_random(HBAO_IMAGES_PARAM int i, int j)    (cos a, sin a, beta) of the tiled texture
//   vec2  hbao_direction(HBAO_IMAGES_PARAM int d)        (cos, sin) of 2 pi d / Nd
//   float hbao_raw_ao(HBAO_IMAGES_PARAM int i, int j)    unblurred AO (the blur pass only)
//   void  hbao_store_horizon(HBAO_IMAGES_PARAM int i, int j, int d, float h2)  H^2 of direction d
//   float hbao_load_horizon(HBAO_IMAGES_PARAM int i, int j, int d)            (between the passes)
//
// Eye space: x right, y up, z forward along the view axis (z = the G-buffer's linear depth); pixel
// (i, j) is seen through the eye-space point ((i + 0.5 - W/2) / f, (H/2 - j - 0.5) / f, 1), with
// f = H / (2 tan(fov_y / 2)) the focal length in pixels (square pixels, CONTRACT §3).

// The eye-space point of pixel (i, j) at linear depth z (§4: "we compute an eye-space position of
// its corresponding surface point P").
vec3 hbao_eye_position(int i, int j, float z, HbaoConstants c) {
  precise float x = (float(i) + 0.5f - c.half_width) / c.focal * z;
  precise float y = (c.half_height - (float(j) + 0.5f)) / c.focal * z;
  return vec3(x, y, z);
}

// Fig. 4 lines 4-5, ISBELOW(Q, S) and INTERSECT(Q - E, S): project Q to the screen, read the
// nearest texel's depth (§4.1.1) and, when that surface lies in front of Q, return its point on the
// eye ray through Q. Outside the screen, behind the eye or over background: not below.
bool hbao_below(HBAO_IMAGES_PARAM vec3 q, HbaoConstants c, HBAO_OUT(vec3) hit) {
  precise float inv_z = 1.0f / q.z;  // one division per step (they dominate on CPU devices)
  precise float focal_z = c.focal * inv_z;
  precise float u = q.x * focal_z + c.half_width;
  precise float v = c.half_height - q.y * focal_z;
  bool inside = q.z > 0.0f && u >= 0.0f && u < float(c.width) && v >= 0.0f && v < float(c.height);
  // The fetch is unconditional (texel 0 stands in outside the screen, and is then ignored): no
  // branch around the load, which SIMD devices (lavapipe) would otherwise mask lane by lane.
  float z = hbao_depth(HBAO_IMAGES_ARG inside ? int(u) : 0, inside ? int(v) : 0);
  if (!(inside && z > 0.0f && z < q.z)) return false;
  precise float scale = z * inv_z;
  hit = q * scale;
  return true;
}

// §3.5: the weight of an occluder at squared distance len2 from P, 1 - r / R (linear), or 1.
float hbao_attenuation(float len2, HbaoConstants c) {
  if (c.attenuation == 0) return 1.0f;
  precise float w = 1.0f - sqrt(len2) / c.radius;
  return w;
}

// §3.1 horizon tracing (Fig. 4) in tangent direction t: the horizon ray h starts as t and is
// deflected towards each intersection I that lies within R and ahead (DOT(I - P, t) > 0) whenever
// that raises it, so H = DOT(h, n) only grows. Returns H(theta)^2, the horizon occlusion of §3.2
// without attenuation. `occlusion` receives T(theta) of eq. 3: H^2 without attenuation; with it
// (§3.5) each rise of the horizon from H_old to H_new is weighted by the attenuation of the occluder
// that caused it, T = sum W(r) (H_new^2 - H_old^2), which telescopes to H^2 when W = 1.
// beta in (-1, 1) jitters the steps: Q = P + (i + beta) (R / Ns) h (§4.1.2).
// The candidate height of I is compared squared, dn^2 > H^2 (dn^2 + dt^2) with dn > 0, so that the
// square root and divisions run only when the horizon rises.
float hbao_trace_horizon(HBAO_IMAGES_PARAM vec3 p, vec3 n, vec3 t, float beta, HbaoConstants c,
                         HBAO_OUT(float) occlusion) {
  precise vec3 h = t;
  precise float h2 = 0.0f;  // DOT(h, n)^2
  precise float occ = 0.0f;
  precise float r2 = c.radius * c.radius;
  for (int s = 1; s <= c.steps; ++s) {
    precise float dist = (float(s) + beta) * c.step;
    precise vec3 q = p + h * dist;
    vec3 hit;
    if (hbao_below(HBAO_IMAGES_ARG q, c, hit)) {
      precise vec3 d = hit - p;
      precise float len2 = hbao_dot(d, d);
      precise float dt = hbao_dot(d, t);
      precise float dn = hbao_dot(d, n);
      precise float dn2 = dn * dn;
      precise float nt2 = dn2 + dt * dt;  // |PROJ_n,t(I - P)|^2
      if (len2 < r2 && dt > 0.0f && dn > 0.0f && dn2 > h2 * nt2) {
        precise float h2_new = dn2 / nt2;
        if (h2_new > h2) {
          precise float rise = h2_new - h2;
          occ = occ + hbao_attenuation(len2, c) * rise;
          h2 = h2_new;
          // h <- NORMALIZE(PROJ_n,t(I - P)) (Fig. 4 line 7).
          precise float len_nt = sqrt(nt2);
          h = (t * dt + n * dn) / len_nt;
        }
      }
    }
  }
  occlusion = occ;
  return h2;
}

// §3.3 linear search along a normal ray r (unit) from P: the attenuated weight of the first
// occluder within R (the V(w) of eq. 7 with §3.5's weight), 0 when the ray escapes.
float hbao_march(HBAO_IMAGES_PARAM vec3 p, vec3 r, float beta, HbaoConstants c) {
  precise float r2 = c.radius * c.radius;
  for (int s = 1; s <= c.steps; ++s) {
    precise float dist = (float(s) + beta) * c.step;
    precise vec3 q = p + r * dist;
    vec3 hit;
    if (hbao_below(HBAO_IMAGES_ARG q, c, hit)) {
      precise vec3 d = hit - p;
      precise float len2 = hbao_dot(d, d);
      if (len2 < r2) return hbao_attenuation(len2, c);
    }
  }
  return 0.0f;
}

// §3.3 normal occlusion of the stripe of direction t above its horizon H (eq. 7-12). The stripe's
// part above the horizon, z^2 in [H^2, 1] (z = DOT(w, n)), holds (1 - H^2) / Nd of the cosine
// measure (eq. 7). With the cosine patch distribution of eq. 8 the Nn patches hold equal shares,
// z_k^2 = H^2 + (1 - H^2) k / Nn, and each ray goes through its patch's middle,
// z^2 = H^2 + (1 - H^2)(k + 1/2) / Nn, r = sqrt(1 - z^2) t + z n (eq. 11). Eq. 10-11 as printed
// start the patches at the tangent plane (k = 0 gives r = t, below the horizon) and drop the
// (1 - H^2) factor of each patch's share; we keep the derivation of eq. 7-8 instead. Returns the
// stripe's occlusion times Nd: (1 - H^2) / Nn sum_k W_k.
float hbao_stripe_normal_occlusion(HBAO_IMAGES_PARAM vec3 p, vec3 n, vec3 t, float h2,
                                   float beta, HbaoConstants c) {
  precise float sum = 0.0f;
  for (int k = 0; k < c.normal_rays; ++k) {
    precise float z2 = h2 + (1.0f - h2) * ((float(k) + 0.5f) / float(c.normal_rays));
    precise float z = sqrt(z2);
    precise float tangential = sqrt(max(1.0f - z2, 0.0f));
    precise vec3 r = t * tangential + n * z;
    sum = sum + hbao_march(HBAO_IMAGES_ARG p, r, beta, c);
  }
  precise float share = (1.0f - h2) * sum / float(c.normal_rays);
  return share;
}

// What both occlusion passes need of a pixel: P' (eq. 13), the normal, a tangent frame and the
// pixel's entry of the tiled random texture (§4.1.2).
struct HbaoPixel {
  vec3 p;      // P' = P + z / (f res) n (eq. 13), or P when the offset is off
  vec3 n;      // unit eye-space normal
  vec3 b1;     // tangent frame (Duff et al. 2017, "Building an Orthonormal Basis, Revisited")
  vec3 b2;
  float ca;    // cos, sin of the per-pixel rotation alpha in [0, 2 pi / Nd)
  float sa;
  float beta;  // step jitter in (-1, 1)
};

bool hbao_setup_pixel(HBAO_IMAGES_PARAM int i, int j, HbaoConstants c, HBAO_OUT(HbaoPixel) px) {
  float z = hbao_depth(HBAO_IMAGES_ARG i, j);
  if (!(z > 0.0f)) return false;
  vec3 n = hbao_normal(HBAO_IMAGES_ARG i, j);
  precise float lift = z * c.offset_scale;
  precise vec3 p = hbao_eye_position(i, j, z, c) + n * lift;
  // Duff et al.'s branchless basis; the sign is taken with a comparison (not copysign) so that
  // both languages treat n.z = -0 alike.
  float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
  precise float a = -1.0f / (sgn + n.z);
  precise float b = n.x * n.y * a;
  px.p = p;
  px.n = n;
  precise vec3 b1 = vec3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
  precise vec3 b2 = vec3(b, sgn + n.y * n.y * a, -n.y);
  px.b1 = b1;
  px.b2 = b2;
  vec3 rnd = hbao_random(HBAO_IMAGES_ARG i, j);
  px.ca = rnd.x;
  px.sa = rnd.y;
  px.beta = rnd.z;
  return true;
}

// The tangent of direction d: theta_d = alpha + 2 pi d / Nd around the normal (§3.1: "Nd times per
// pixel for randomly distributed angles theta"), by the angle-sum formulas on tabulated values.
vec3 hbao_tangent(HBAO_IMAGES_PARAM HbaoPixel px, int d) {
  vec2 cs = hbao_direction(HBAO_IMAGES_ARG d);
  precise float ct = px.ca * cs.x - px.sa * cs.y;
  precise float st = px.sa * cs.x + px.ca * cs.y;
  precise vec3 t = px.b1 * ct + px.b2 * st;
  return t;
}

// Pass 1, horizon occlusion (§3.2): traces the Nd horizons of pixel (i, j), stores each H(theta_d)^2
// for pass 2 and returns O_T = (1/Nd) sum_d T(theta_d) (eq. 5-6: each lune subtends 2 pi / Nd).
float hbao_horizon_pass(HBAO_IMAGES_PARAM int i, int j, HbaoConstants c) {
  HbaoPixel px;
  if (!hbao_setup_pixel(HBAO_IMAGES_ARG i, j, c, px)) return 0.0f;
  precise float sum = 0.0f;
  for (int d = 0; d < c.directions; ++d) {
    vec3 t = hbao_tangent(HBAO_IMAGES_ARG px, d);
    float occlusion;
    float h2 = hbao_trace_horizon(HBAO_IMAGES_ARG px.p, px.n, t, px.beta, c, occlusion);
    hbao_store_horizon(HBAO_IMAGES_ARG i, j, d, h2);
    sum = sum + occlusion;
  }
  precise float ot = sum / float(c.directions);
  return ot;
}

// Pass 2, normal occlusion (§3.3) above the stored horizons, and the combination of §3.4:
// A = 1 - (O_T + O_N), clamped to [0, 1] (attenuated weights keep it inside; the clamp only guards
// rounding).
float hbao_normal_pass(HBAO_IMAGES_PARAM int i, int j, float ot, HbaoConstants c) {
  HbaoPixel px;
  if (!hbao_setup_pixel(HBAO_IMAGES_ARG i, j, c, px)) return 0.0f;
  precise float sum = 0.0f;
  if (c.normal_rays > 0) {
    for (int d = 0; d < c.directions; ++d) {
      vec3 t = hbao_tangent(HBAO_IMAGES_ARG px, d);
      float h2 = hbao_load_horizon(HBAO_IMAGES_ARG i, j, d);
      sum = sum + hbao_stripe_normal_occlusion(HBAO_IMAGES_ARG px.p, px.n, t, h2, px.beta, c);
    }
  }
  precise float on = sum / float(c.directions);
  precise float ao = 1.0f - (ot + on);
  return min(max(ao, 0.0f), 1.0f);
}

// §4.1.3 blur: a 5x5 Gaussian (the binomial 1 4 6 4 1, sigma = 1 pixel) over covered pixels, each
// further weighted by the inverse of its depth deviation from the centre, measured in pixel
// footprints at the centre's depth (z / f) and offset by 1 so that the centre's weight stays finite:
// w = g / (1 + |z - z_c| / (z_c / f)).
float hbao_binomial(int k) {
  return (k == 0 || k == 4) ? 1.0f : (k == 2 ? 6.0f : 4.0f);
}

float hbao_blur(HBAO_IMAGES_PARAM int i, int j, HbaoConstants c) {
  float zc = hbao_depth(HBAO_IMAGES_ARG i, j);
  if (!(zc > 0.0f)) return 0.0f;
  precise float footprint = zc / c.focal;
  precise float sum = 0.0f;
  precise float weights = 0.0f;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      int x = i + dx;
      int y = j + dy;
      if (x < 0 || y < 0 || x >= c.width || y >= c.height) continue;
      float z = hbao_depth(HBAO_IMAGES_ARG x, y);
      if (!(z > 0.0f)) continue;
      precise float g = hbao_binomial(dx + 2) * hbao_binomial(dy + 2);
      precise float w = g / (1.0f + abs(z - zc) / footprint);
      sum = sum + w * hbao_raw_ao(HBAO_IMAGES_ARG x, y);
      weights = weights + w;
    }
  }
  precise float ao = sum / weights;
  return ao;
}
