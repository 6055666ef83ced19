// Horizon-split ambient occlusion, per pixel: Dimitrov, Bavoil, Sainz 2008, "Horizon-Split Ambient
// Occlusion". ONE source for both twins: the Vulkan compute shaders include it as GLSL 4.50, the
// CPU twin (hbao_cpu.cpp) includes it as C++ through screen_space/glsl_compat.h. So it uses only spellings both
// languages share (float literals with an f suffix, float()/int() casts, `precise` on every result
// that could be contracted into an fma, GLSL_OUT / GLSL_INOUT for out / inout parameters) and the
// same operations in the same order, which is what makes the twins agree to 1e-3
// (hbao_split_test.cpp).
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
// and the texel index of an image coordinate, clamped into [0, size): int hbao_texel(float u,
// int size) (the same on both sides wherever int(u) is defined; beyond int's range, or NaN, the
// languages differ, and that texel is read and then ignored: the point is off the screen).
//
// Eye space: x right, y up, z forward along the view axis (z = the G-buffer's linear depth); pixel
// (i, j) is seen through the eye-space point ((i + 0.5 - W/2) / f, (H/2 - j - 0.5) / f, 1), with
// f = H / (2 tan(fov_y / 2)) the focal length in pixels (square pixels, CONTRACT §3).

// a . b, written out so that both twins sum in the same order.
float hbao_dot(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

// The eye-space point of pixel (i, j) at linear depth z (§4: "we compute an eye-space position of
// its corresponding surface point P").
vec3 hbao_eye_position(int i, int j, float z, HbaoConstants c) {
  precise float x = (float(i) + 0.5f - c.half_width) / c.focal * z;
  precise float y = (c.half_height - (float(j) + 0.5f)) / c.focal * z;
  return vec3(x, y, z);
}

// Points and directions of the searches are kept in screen-scaled form,
// S(v) = (f v.x + (W/2) v.z, (H/2) v.z - f v.y, v.z): S is linear, so the step Q = P + d h is
// S(Q) = S(P) + d S(h) (three multiply-adds), and Q projects to pixel (S(Q).x / Q.z, S(Q).y / Q.z)
// with one division and two products, with nothing else to form per step.
vec3 hbao_screen(vec3 v, HbaoConstants c) {
  precise float x = c.focal * v.x + c.half_width * v.z;
  precise float y = c.half_height * v.z - c.focal * v.y;
  return vec3(x, y, v.z);
}

// Fig. 4 lines 4-5, ISBELOW(Q, S) and INTERSECT(Q - E, S): project Q (given as S(Q)) to the
// screen and read the nearest texel's depth z (§4.1.1); Q is below the surface when that surface
// lies in front of it, z < Q.z, and then the intersection is the surface's point I = (z / Q.z) Q
// on the eye ray through Q. Gives z and 1 / Q.z. Outside the screen, behind the eye or over
// background: not below.
bool hbao_below(HBAO_IMAGES_PARAM vec3 sq, HbaoConstants c, GLSL_OUT(float) depth,
                GLSL_OUT(float) inv_qz) {
  precise float inv_z = 1.0f / sq.z;  // the step's one division
  precise float u = sq.x * inv_z;
  precise float v = sq.y * inv_z;
  // The fetch is unconditional and its texel is clamped into the image (a point outside the
  // screen reads an edge texel, which is then ignored): its address then waits only on u and v,
  // not on the tests below, and there is no branch around the load, which SIMD devices (lavapipe)
  // would otherwise mask lane by lane.
  float z = hbao_depth(HBAO_IMAGES_ARG hbao_texel(u, c.width), hbao_texel(v, c.height));
  bool inside = u >= 0.0f && u < float(c.width) && v >= 0.0f && v < float(c.height);
  depth = z;
  inv_qz = inv_z;
  return inside && z > 0.0f && z < sq.z;  // z > 0 and z < Q.z: Q is in front of the eye
}

// §3.5: the weight of an occluder at squared distance len2 from P, 1 - r / R (linear), or 1.
float hbao_attenuation(float len2, HbaoConstants c) {
  // 1 - r * 0 = 1 when attenuation is off: no select (SIMD devices run both sides of an if).
  // The factor is the same for the whole dispatch, so compilers hoist it out of the loops.
  precise float w = 1.0f - sqrt(len2) * (float(c.attenuation) / c.radius);
  return w;
}

// Directions traced together, in one loop over the steps. Each direction's walk is a chain of
// dependent operations (the next step's position depends on the horizon that this step's fetch
// may raise), which leaves a CPU device (lavapipe) waiting on the latency of each fetch and
// division; HBAO_GROUP independent walks give it work to overlap. Each direction's arithmetic is
// the same whatever the group size. Normal rays (hbao_normal_pass) are searched HBAO_RAY_GROUP
// directions at a time: a ray's state is smaller, so eight fit. Measured on bunny 640x480 on
// lavapipe (Nd = 8): horizon group 2 / 4 / 8 = 62 / 41 / 37 ms; 4 wastes fewer slots when Nd is
// not a multiple of 8 (Nd = 7 in Table 1, 18 in the quality preset); normal rays 4 / 8 = 32 / 30
// ms (earlier kernel).
#define HBAO_GROUP 4
#define HBAO_RAY_GROUP 8

// One direction's horizon while it is traced: h = ht t + hn n (unit, in the plane of t and n).
// Only (ht, hn) and the occlusion so far are kept: four directions' state, with what their walks
// read (HbaoWalk), must fit the 32 vector registers of a CPU device.
struct HbaoHorizon {
  float ht;   // DOT(h, t)
  float hn;   // DOT(h, n) = H(theta)
  float occ;  // T(theta) so far
};

// What a direction's walk needs of t, fixed along the walk (the pixel's S(P), S(n) and DOT(P, n)
// are passed beside it).
struct HbaoWalk {
  vec3 st;   // S(t)
  float pt;  // DOT(P, t)
  float pb;  // DOT(P, n x t) = DOT(t, P x n): P's component out of the plane of t and n
};

// §3.1 horizon tracing (Fig. 4), step i of direction t at distance dist = (i + beta) R / Ns along
// the current horizon ray, Q = P + dist h (beta in (-1, 1) jitters the steps, §4.1.2). The
// horizon ray starts as t and is deflected towards each intersection I that lies within R and
// ahead (DOT(I - P, t) > 0) whenever that raises it, so H = DOT(h, n) only grows. `occ`
// accumulates T(theta) of eq. 3: H^2 without attenuation; with it (§3.5) each rise from H_old to
// H_new is weighted by the attenuation of the occluder that caused it,
// T = sum W(r) (H_new^2 - H_old^2), which telescopes to H^2 when W = 1.
// With I = s Q, s = z / Q.z (hbao_below), I - P = (s - 1) P + s dist h, so its components in
// the frame (t, n, n x t) are (s - 1) DOT(P, t) + s dist ht, (s - 1) DOT(P, n) + s dist hn and
// (s - 1) DOT(P, n x t): no vector operation beyond the step itself. The candidate height is
// compared squared, dn^2 > H^2 (dn^2 + dt^2) with dn > 0.
// On a SIMD CPU device (lavapipe) both sides of every `if` run, each value assigned under one
// costs a select, and values that do not fit the registers are spilled. What made this loop fast
// there (horizon pass, bunny 640x480, one machine): state cut to (ht, hn, occ) per direction with
// the step formed from S(t), S(n) (61 -> 46 ms, against keeping S(h) as state), attenuation
// without a select (46 -> 40 ms), fetch addresses clamped rather than selected (65 -> 61 ms).
void hbao_horizon_step(HBAO_IMAGES_PARAM vec3 sp, vec3 sn, float pn, HbaoWalk w, float dist,
                       HbaoConstants c, GLSL_INOUT(HbaoHorizon) hz) {
  precise float at = dist * hz.ht;
  precise float an = dist * hz.hn;
  precise vec3 sq = sp + w.st * at + sn * an;  // S(Q), Q = P + dist (ht t + hn n)
  float z;
  float inv_z;
  bool below = hbao_below(HBAO_IMAGES_ARG sq, c, z, inv_z);
  precise float s = z * inv_z;
  precise float s1 = s - 1.0f;
  precise float dt = s1 * w.pt + s * at;
  precise float dn = s1 * pn + s * an;
  precise float db = s1 * w.pb;
  precise float dn2 = dn * dn;
  precise float nt2 = dn2 + dt * dt;   // |PROJ_n,t(I - P)|^2
  precise float len2 = nt2 + db * db;  // |I - P|^2
  precise float h2 = hz.hn * hz.hn;
  precise float r2 = c.radius * c.radius;
  if (below && len2 < r2 && dt > 0.0f && dn > 0.0f && dn2 > h2 * nt2) {
    // h <- NORMALIZE(PROJ_n,t(I - P)) (Fig. 4 line 7), and its new height H = DOT(h, n).
    precise float inv_len = 1.0f / sqrt(nt2);
    precise float ht = dt * inv_len;
    precise float hn = dn * inv_len;
    precise float h2_new = hn * hn;
    if (h2_new > h2) {
      precise float occ_new = hz.occ + hbao_attenuation(len2, c) * (h2_new - h2);
      hz.occ = occ_new;
      hz.ht = ht;
      hz.hn = hn;
    }
  }
}

// §3.3 linear search along a normal ray r (unit) from P, one step at distance dist: records
// |I - P|^2 of the first occluder within R in hit_len2 (< 0 until there is one). The ray is given
// as S(P), S(r) (hbao_screen); with I = s Q, I - P = (s - 1) P + s dist r, so |I - P|^2 follows
// from pr = DOT(P, r) and pp = |P|^2.
void hbao_march_step(HBAO_IMAGES_PARAM vec3 sp, vec3 sr, float pr, float pp, float dist,
                     HbaoConstants c, GLSL_INOUT(float) hit_len2) {
  precise vec3 sq = sp + sr * dist;
  float z;
  float inv_z;
  bool below = hbao_below(HBAO_IMAGES_ARG sq, c, z, inv_z);
  precise float s = z * inv_z;
  precise float s1 = s - 1.0f;
  precise float ds = s * dist;
  precise float len2 = s1 * (s1 * pp + 2.0f * ds * pr) + ds * ds;
  if (below && hit_len2 < 0.0f && len2 < c.radius * c.radius) hit_len2 = len2;
}

// The weight of a searched ray: §3.5's attenuation of its first occluder (the V(w) of eq. 7 with
// that weight), 0 when it escaped. Weighted after the search: in a SIMD loop body the square
// root and division would run every step.
float hbao_ray_weight(float hit_len2, HbaoConstants c) {
  return hit_len2 < 0.0f ? 0.0f : hbao_attenuation(hit_len2, c);
}

// The whole search along one ray r (unit) from P (raymarch-ssao's rays). A scalar device stops at
// the first occluder; a SIMD device (lavapipe) goes on, because a lane that leaves a loop early
// makes the loop counter, hence the next fetch's address, wait for this step's fetch (llvm-mca on
// the compiled loop: 161 cycles a step with the early exit, 18 without the wait).
float hbao_march(HBAO_IMAGES_PARAM vec3 p, vec3 r, float beta, HbaoConstants c) {
  vec3 sp = hbao_screen(p, c);
  vec3 sr = hbao_screen(r, c);
  float pr = hbao_dot(p, r);
  float pp = hbao_dot(p, p);
  float hit_len2 = -1.0f;
  for (int s = 1; s <= c.steps; ++s) {
#ifdef HBAO_SCALAR_DEVICE
    if (hit_len2 >= 0.0f) break;
#endif
    precise float dist = (float(s) + beta) * c.step;
    hbao_march_step(HBAO_IMAGES_ARG sp, sr, pr, pp, dist, c, hit_len2);
  }
  return hbao_ray_weight(hit_len2, c);
}

// §3.3 normal occlusion of the stripe of direction t above its horizon H (eq. 7-12). The stripe's
// part above the horizon, z^2 in [H^2, 1] (z = DOT(w, n)), holds (1 - H^2) / Nd of the cosine
// measure (eq. 7). With the cosine patch distribution of eq. 8 the Nn patches hold equal shares,
// z_k^2 = H^2 + (1 - H^2) k / Nn, and each ray goes through its patch's middle,
// z^2 = H^2 + (1 - H^2)(k + 1/2) / Nn, r = sqrt(1 - z^2) t + z n (eq. 11). Eq. 10-11 as printed
// start the patches at the tangent plane (k = 0 gives r = t, below the horizon) and drop the
// (1 - H^2) factor of each patch's share; we keep the derivation of eq. 7-8 instead. The stripe's
// occlusion times Nd is (1 - H^2) / Nn sum_k W_k (hbao_normal_pass).
vec3 hbao_normal_ray(vec3 n, vec3 t, float h2, int k, HbaoConstants c) {
  precise float z2 = h2 + (1.0f - h2) * ((float(k) + 0.5f) / float(c.normal_rays));
  precise float z = sqrt(z2);
  precise float tangential = sqrt(max(1.0f - z2, 0.0f));
  precise vec3 r = t * tangential + n * z;
  return r;
}

// What both occlusion passes need of a pixel: P' (eq. 13), the normal, a tangent frame and the
// pixel's entry of the tiled random texture (§4.1.2).
struct HbaoPixel {
  vec3 p;   // P' = P + z / (f res) n (eq. 13), or P when the offset is off
  vec3 n;   // unit eye-space normal
  vec3 b1;  // tangent frame (Duff et al. 2017, "Building an Orthonormal Basis, Revisited")
  vec3 b2;
  float ca;  // cos, sin of the per-pixel rotation alpha in [0, 2 pi / Nd)
  float sa;
  float beta;  // step jitter in (-1, 1)
};

bool hbao_setup_pixel(HBAO_IMAGES_PARAM int i, int j, HbaoConstants c, GLSL_OUT(HbaoPixel) px) {
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

// Pass 1, horizon occlusion (§3.2): traces the Nd horizons of pixel (i, j), HBAO_GROUP directions
// at a time, stores each H(theta_d)^2 for pass 2 and returns O_T = (1/Nd) sum_d T(theta_d)
// (eq. 5-6: each lune subtends 2 pi / Nd). Slots past Nd in the last group count for nothing.
float hbao_horizon_pass(HBAO_IMAGES_PARAM int i, int j, HbaoConstants c) {
  HbaoPixel px;
  if (!hbao_setup_pixel(HBAO_IMAGES_ARG i, j, c, px)) return 0.0f;
  vec3 sp = hbao_screen(px.p, c);
  vec3 sn = hbao_screen(px.n, c);
  float pn = hbao_dot(px.p, px.n);
  precise vec3 pxn = vec3(px.p.y * px.n.z - px.p.z * px.n.y, px.p.z * px.n.x - px.p.x * px.n.z,
                          px.p.x * px.n.y - px.p.y * px.n.x);  // P x n
  precise float sum = 0.0f;
  for (int d0 = 0; d0 < c.directions; d0 += HBAO_GROUP) {
    HbaoWalk w[HBAO_GROUP];
    HbaoHorizon hz[HBAO_GROUP];
    for (int k = 0; k < HBAO_GROUP; ++k) {
      vec3 t = hbao_tangent(HBAO_IMAGES_ARG px, min(d0 + k, c.directions - 1));
      w[k].st = hbao_screen(t, c);
      w[k].pt = hbao_dot(px.p, t);
      w[k].pb = hbao_dot(t, pxn);
      hz[k].ht = 1.0f;
      hz[k].hn = 0.0f;
      hz[k].occ = 0.0f;
    }
    for (int s = 1; s <= c.steps; ++s) {
      precise float dist = (float(s) + px.beta) * c.step;
      for (int k = 0; k < HBAO_GROUP; ++k) {
#ifdef HBAO_SCALAR_DEVICE
        if (d0 + k >= c.directions) continue;  // SIMD: traced again, discarded (no masking)
#endif
        hbao_horizon_step(HBAO_IMAGES_ARG sp, sn, pn, w[k], dist, c, hz[k]);
      }
    }
    for (int k = 0; k < HBAO_GROUP; ++k) {
      if (d0 + k < c.directions) {
        precise float h2 = hz[k].hn * hz[k].hn;
        hbao_store_horizon(HBAO_IMAGES_ARG i, j, d0 + k, h2);
        sum = sum + hz[k].occ;
      }
    }
  }
  precise float ot = sum / float(c.directions);
  return ot;
}

// Pass 2, normal occlusion (§3.3) above the stored horizons, and the combination of §3.4:
// A = 1 - (O_T + O_N), clamped to [0, 1] (attenuated weights keep it inside; the clamp only guards
// rounding). The rays of HBAO_RAY_GROUP directions are searched together, as the horizons are.
float hbao_normal_pass(HBAO_IMAGES_PARAM int i, int j, float ot, HbaoConstants c) {
  HbaoPixel px;
  if (!hbao_setup_pixel(HBAO_IMAGES_ARG i, j, c, px)) return 0.0f;
  vec3 sp = hbao_screen(px.p, c);
  float pp = hbao_dot(px.p, px.p);
  precise float sum = 0.0f;
  if (c.normal_rays > 0) {
    for (int d0 = 0; d0 < c.directions; d0 += HBAO_RAY_GROUP) {
      vec3 t[HBAO_RAY_GROUP];
      float h2[HBAO_RAY_GROUP];
      float weights[HBAO_RAY_GROUP];  // sum_k W_k of the stripe
      for (int k = 0; k < HBAO_RAY_GROUP; ++k) {
        int d = min(d0 + k, c.directions - 1);
        t[k] = hbao_tangent(HBAO_IMAGES_ARG px, d);
        h2[k] = hbao_load_horizon(HBAO_IMAGES_ARG i, j, d);
        weights[k] = 0.0f;
      }
      for (int m = 0; m < c.normal_rays; ++m) {
        vec3 sr[HBAO_RAY_GROUP];
        float pr[HBAO_RAY_GROUP];
        float hit_len2[HBAO_RAY_GROUP];
        for (int k = 0; k < HBAO_RAY_GROUP; ++k) {
          vec3 r = hbao_normal_ray(px.n, t[k], h2[k], m, c);
          sr[k] = hbao_screen(r, c);
          pr[k] = hbao_dot(px.p, r);
          hit_len2[k] = d0 + k < c.directions ? -1.0f : 0.0f;  // slots past Nd: nothing to find
        }
        for (int s = 1; s <= c.steps; ++s) {
          precise float dist = (float(s) + px.beta) * c.step;
          for (int k = 0; k < HBAO_RAY_GROUP; ++k) {
#ifdef HBAO_SCALAR_DEVICE
            if (hit_len2[k] >= 0.0f) continue;  // a scalar device skips finished rays
#endif
            hbao_march_step(HBAO_IMAGES_ARG sp, sr[k], pr[k], pp, dist, c, hit_len2[k]);
          }
        }
        for (int k = 0; k < HBAO_RAY_GROUP; ++k) {
          precise float w = weights[k] + hbao_ray_weight(hit_len2[k], c);
          weights[k] = w;
        }
      }
      for (int k = 0; k < HBAO_RAY_GROUP; ++k) {
        if (d0 + k < c.directions) {
          precise float share = (1.0f - h2[k]) * weights[k] / float(c.normal_rays);
          sum = sum + share;
        }
      }
    }
  }
  precise float on = sum / float(c.directions);
  precise float ao = 1.0f - (ot + on);
  return min(max(ao, 0.0f), 1.0f);
}

// §4.1.3 blur: a 5x5 Gaussian (the binomial 1 4 6 4 1, sigma = 1 pixel) over covered pixels, each
// further weighted by the inverse of its depth deviation from the centre, measured in pixel
// footprints at the centre's depth (z / f) and offset by 1 so that the centre's weight stays
// finite: w = g / (1 + |z - z_c| / (z_c / f)).
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
