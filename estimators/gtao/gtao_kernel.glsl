// Ground-truth ambient occlusion (GTAO), per pixel: Jimenez, Wu, Pesce, Jarabo 2016, "Practical
// Real-Time Strategies for Accurate Indirect Occlusion" (SIGGRAPH 2016 course / Activision
// technical report ATVI-TR-16-01). ONE source for both twins: the Vulkan compute shaders include it
// as GLSL 4.50 (gtao_common.glsl), the CPU twin (gtao_cpu.cpp) as C++ through screen_space/glsl_compat.h.
// It therefore uses only spellings both languages share (float literals with an f suffix,
// float()/int() casts, `precise` on every result that could be contracted into an fma, GLSL_OUT
// for out parameters) and calls no transcendental function: the horizon angles come from a
// polynomial arccosine (gtao_acos; the paper itself replaces acos by a polynomial for speed), the
// slice directions from a table and a per-pixel rotation computed on the host in double, and the
// closed forms below are written with the sines and cosines of the horizon and normal angles
// themselves. With + - * / and sqrt only, both sides round every operation alike (IEEE 754), so the
// twins agree bit for bit wherever the devices do (gtao_test.cpp measures it).
//
// The paper's formulation, which this file follows (equation numbers of the technical report are
// quoted with the formula itself, since the course notes number them differently):
//  - AO with cosine weighting, A(x) = (1/pi) Int_{H2} V(w) (n . w)+ dw (the paper's eq. 1, CONTRACT
//    §3 cosine), written in polar coordinates around the view vector v (from the point to the
//    eye): slices phi in [0, pi) that contain v, angle theta from v inside each slice, and the
//    Jacobian |sin theta| (the paper's eq. 3): A = (1/pi) Int_0^pi Int V (n . w)+ |sin theta|.
//  - In slice phi the normal is split into its projection n_p onto the slice plane, of length
//    |n_p| and angle gamma from v, so n . w = |n_p| cos(theta - gamma) (the paper's eq. 4-6).
//  - Visibility in the slice is taken as the arc between the two horizons h1 <= 0 <= h2 (the
//    highest occluder seen on each side within the radius), clamped to the normal's hemisphere,
//    h1 >= gamma - pi/2, h2 <= gamma + pi/2 (the paper's eq. 7-8).
//  - The inner integral in closed form (the paper's eq. 10, "a^"):
//      a(h1, h2) = 1/4 (-cos(2 h1 - gamma) + cos gamma + 2 h1 sin gamma)
//                + 1/4 (-cos(2 h2 - gamma) + cos gamma + 2 h2 sin gamma),
//    and A = (1/pi) Int_0^pi |n_p| a dphi, estimated with `slices` evenly spaced slices rotated
//    per pixel (the paper's spatial noise, §5.2), A ~ (1/slices) sum |n_p| a.
//  - The bent normal, the cosine-weighted mean unoccluded direction (the paper's bent-normal
//    extension, its Algorithm 2): Int w cos(theta - gamma) |sin theta| dtheta over [h1, h2] in
//    closed form (gtao_slice_bent), summed over slices with the weight |n_p|.
//
// Before including it, each side defines the accessors of the inputs:
//   float gtao_depth(GTAO_IMAGES_PARAM int i, int j)        linear view depth z > 0, 0 = background
//   vec3  gtao_normal(GTAO_IMAGES_PARAM int i, int j)       unit eye-space normal, facing the viewer
//   vec2  gtao_rotation(GTAO_IMAGES_PARAM int i, int j)     (cos, sin) of the pixel's slice rotation
//   float gtao_step(GTAO_IMAGES_PARAM int i, int j, int k)  the pixel's sample distance k in [0, 1)
//   vec2  gtao_slice(GTAO_IMAGES_PARAM int s)               (cos, sin) of pi s / slices
//   float gtao_raw_ao(GTAO_IMAGES_PARAM int i, int j)       (denoise pass) AO before the filter
//   vec3  gtao_raw_bent(GTAO_IMAGES_PARAM int i, int j)     (denoise pass) bent normal before it
// and gtao_floor(float) -> int (GLSL: int(floor(u)); see gtao_cpu_kernel.h for C++).
//
// Eye space: x right, y up, z forward along the view axis (z = the G-buffer's linear depth); the
// continuous image point (x, y) (pixel (i, j) has its centre at (i + 0.5, j + 0.5), row 0 at the
// top) is seen through ((x - W/2) / f, (H/2 - y) / f, 1), f = H / (2 tan(fov_y / 2)).

float gtao_dot(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

vec3 gtao_cross(vec3 a, vec3 b) {
  precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return r;
}

// The eye-space point seen through image point (x, y) at linear depth z.
vec3 gtao_eye_position(float x, float y, float z, GtaoConstants c) {
  precise float ex = (x - c.half_width) / c.focal * z;
  precise float ey = (c.half_height - y) / c.focal * z;
  return vec3(ex, ey, z);
}

// arccos(x) for x in [-1, 1] (clamped): Abramowitz and Stegun 4.4.46,
// acos(a) = sqrt(1 - a) (a0 + a1 a + ... + a7 a^7) on [0, 1], |error| <= 2e-8 rad, and
// acos(-a) = pi - acos(a). The paper (§5) replaces acos by a polynomial for speed; here it also
// makes both twins compute the same bits (no libm or driver transcendental).
float gtao_acos(float x) {
  float a = min(abs(x), 1.0f);
  precise float q = -0.0012624911f * a + 0.0066700901f;
  q = q * a - 0.0170881256f;
  q = q * a + 0.0308918810f;
  q = q * a - 0.0501743046f;
  q = q * a + 0.0889789874f;
  q = q * a - 0.2145988016f;
  q = q * a + 1.5707963050f;
  precise float r = sqrt(1.0f - a) * q;
  precise float m = 3.14159265f - r;
  return x >= 0.0f ? r : m;
}

// The depth seen at image point (x, y): inverse depth 1/z interpolated bilinearly between the four
// nearest texel centres. On a plane 1/z is an affine function of the image coordinates, so the
// point rebuilt from it lies on the plane and on the slice's eye plane exactly (up to rounding):
// no staircase (the nearest-texel one needs hbao-split's eq. 13 offset) and no sample off the
// slice, the two sources of false occlusion on flat surfaces at grazing angles. False where a
// texel is missing (outside the image or background): such a sample is ignored.
bool gtao_sample_depth(GTAO_IMAGES_PARAM float x, float y, GtaoConstants c, GLSL_OUT(float) z) {
  precise float gx = x - 0.5f;
  precise float gy = y - 0.5f;
  int x0 = gtao_floor(gx);
  int y0 = gtao_floor(gy);
  bool inside = x0 >= 0 && y0 >= 0 && x0 + 1 < c.width && y0 + 1 < c.height;
  // Clamped, so that the fetches are unconditional (SIMD devices mask no branch around them).
  int cx = clamp(x0, 0, c.width - 2);
  int cy = clamp(y0, 0, c.height - 2);
  float z00 = gtao_depth(GTAO_IMAGES_ARG cx, cy);
  float z10 = gtao_depth(GTAO_IMAGES_ARG cx + 1, cy);
  float z01 = gtao_depth(GTAO_IMAGES_ARG cx, cy + 1);
  float z11 = gtao_depth(GTAO_IMAGES_ARG cx + 1, cy + 1);
  bool covered = z00 > 0.0f && z10 > 0.0f && z01 > 0.0f && z11 > 0.0f;
  if (!(inside && covered)) {
    z = 0.0f;
    return false;
  }
  precise float fx = gx - float(cx);
  precise float fy = gy - float(cy);
  precise float i00 = 1.0f / z00;
  precise float i10 = 1.0f / z10;
  precise float i01 = 1.0f / z01;
  precise float i11 = 1.0f / z11;
  precise float top = i00 + (i10 - i00) * fx;
  precise float bottom = i01 + (i11 - i01) * fx;
  precise float inv = top + (bottom - top) * fy;
  precise float zs = 1.0f / inv;
  z = zs;
  return true;
}

// One sample of a horizon search at image point (x, y): the cosine of the angle between v and the
// direction from P to the sample (the paper's horizon, measured as cos h, eq. 7), weighted towards
// the side's tangent-plane horizon `low` by the falloff (1 within (1 - falloff) R, 0 at and beyond
// R = dmax), and merged into the running horizon hc: a higher sample raises it (the plain max of
// eq. 7); a lower one pulls it down by the fraction `thickness` (thin-occluder compensation, the
// paper's thickness heuristic, §4: an occluder seen in front of lower samples is taken to be thin;
// 0 = off, the exact horizon of a heightfield).
float gtao_horizon_sample(GTAO_IMAGES_PARAM float x, float y, vec3 p, vec3 v, float low, float hc,
                          GtaoConstants c) {
  float zs;
  bool ok = gtao_sample_depth(GTAO_IMAGES_ARG x, y, c, zs);
  vec3 q = gtao_eye_position(x, y, zs, c);
  precise vec3 delta = q - p;
  precise float dist = sqrt(gtao_dot(delta, delta));
  precise float ch = gtao_dot(delta, v) / dist;
  precise float w = clamp((c.radius - dist) * c.falloff_mul, 0.0f, 1.0f);
  precise float weighted = low + (ch - low) * w;
  float shc = (ok && dist > 0.0f) ? max(weighted, low) : low;
  precise float relaxed = hc + (shc - hc) * c.thickness;
  return shc > hc ? shc : relaxed;
}

// The closed-form inner integral of the paper's eq. 10 over [h1, h2] (h1 <= 0 <= h2), written with
// the horizons' cosines ch and sines sh (sh1 <= 0 <= sh2) and the normal's cg = cos gamma,
// sg = sin gamma: Int_h1^h2 cos(theta - gamma) |sin theta| dtheta
//   = cg (sh1^2 + sh2^2) / 2 + sg (h1 + h2 - sh1 ch1 - sh2 ch2) / 2,
// which is the paper's 1/4 (-cos(2h - gamma) + cos gamma + 2h sin gamma) summed over both sides
// (cos(2h - gamma) = (ch^2 - sh^2) cg + 2 sh ch sg). The unoccluded slice
// (h = gamma -+ pi/2) gives cos gamma + gamma sin gamma.
float gtao_slice_ao(float ch1, float sh1, float h1, float ch2, float sh2, float h2, float cg,
                    float sg) {
  precise float a = cg * (sh1 * sh1 + sh2 * sh2) * 0.5f;
  precise float b = sg * (h1 + h2 - sh1 * ch1 - sh2 * ch2) * 0.5f;
  precise float r = a + b;
  return r;
}

// The bent-normal integrals of one slice (the paper's Algorithm 2 extension), in the slice's frame
// (d along the slice, perpendicular to v; v towards the eye): w = sin theta d + cos theta v, and
// Int w cos(theta - gamma) |sin theta| dtheta over [h1, h2] = (B_d, B_v) with the antiderivatives
//   F_d(theta) = cg sin^3/3 + sg (cos^3/3 - cos),   F_v(theta) = sg sin^3/3 - cg cos^3/3
// (|sin theta| = -sin theta on the h1 side): B = F(h1) + F(h2) - 2 F(0), F_d(0) = -2 sg / 3,
// F_v(0) = -cg / 3. The unoccluded slice gives (4 sg / 3, 2 cg / 3).
vec2 gtao_slice_bent(float ch1, float sh1, float ch2, float sh2, float cg, float sg) {
  precise float s1 = sh1 * sh1 * sh1;
  precise float s2 = sh2 * sh2 * sh2;
  precise float c1 = ch1 * ch1 * ch1;
  precise float c2 = ch2 * ch2 * ch2;
  precise float bd = cg * (s1 + s2) / 3.0f + sg * ((c1 + c2) / 3.0f - ch1 - ch2) + sg * 4.0f / 3.0f;
  precise float bv = sg * (s1 + s2) / 3.0f - cg * (c1 + c2) / 3.0f + cg * 2.0f / 3.0f;
  return vec2(bd, bv);
}

// GTAO of pixel (i, j) before the denoise pass: returns AO in [0, 1] and writes the unit eye-space
// bent normal (0 where nothing is visible or the pixel is not covered).
float gtao_pixel(GTAO_IMAGES_PARAM int i, int j, GtaoConstants c, GLSL_OUT(vec3) bent) {
  bent = vec3(0.0f, 0.0f, 0.0f);
  float z = gtao_depth(GTAO_IMAGES_ARG i, j);
  if (!(z > 0.0f)) return 0.0f;
  float px = float(i) + 0.5f;
  float py = float(j) + 0.5f;
  vec3 p = gtao_eye_position(px, py, z, c);
  vec3 n = gtao_normal(GTAO_IMAGES_ARG i, j);
  precise float inv_len = 1.0f / sqrt(gtao_dot(p, p));
  precise vec3 v = p * (-inv_len);  // towards the eye
  // An orthonormal basis (e1, e2) of the plane perpendicular to v: the slices' angle phi is
  // measured in it, uniformly as the paper's polar coordinates around v require (eq. 3). (Taking
  // the directions uniform on the screen instead would weight slices unevenly off the view axis.)
  precise vec3 e1r = vec3(1.0f, 0.0f, 0.0f) - v * v.x;
  precise float e1_inv = 1.0f / sqrt(gtao_dot(e1r, e1r));
  precise vec3 e1 = e1r * e1_inv;
  vec3 e2 = gtao_cross(v, e1);
  vec2 rot = gtao_rotation(GTAO_IMAGES_ARG i, j);
  precise float radius_px = c.radius_scale / z;  // R seen at depth z, pixels
  precise float sum = 0.0f;
  precise float open = 0.0f;
  precise vec3 bent_sum = vec3(0.0f, 0.0f, 0.0f);
  for (int s = 0; s < c.slices; ++s) {
    vec2 cs = gtao_slice(GTAO_IMAGES_ARG s);
    precise float cphi = rot.x * cs.x - rot.y * cs.y;
    precise float sphi = rot.y * cs.x + rot.x * cs.y;
    precise vec3 d = e1 * cphi + e2 * sphi;  // the slice's direction, unit, perpendicular to v
    vec3 axis = gtao_cross(d, v);            // the slice plane's normal, unit
    precise float na = gtao_dot(n, axis);
    precise vec3 np = n - axis * na;  // n projected onto the slice plane (eq. 4)
    precise float np_len = sqrt(gtao_dot(np, np));
    float cg = 1.0f;
    float sg = 0.0f;
    if (np_len > 1.0e-6f) {
      precise float cgr = gtao_dot(np, v) / np_len;
      precise float sgr = gtao_dot(np, d) / np_len;
      cg = cgr;
      sg = sgr;
    }
    if (cg < 0.0f) {  // a shading normal turned slightly away from the eye: gamma = +-pi/2
      cg = 0.0f;
      sg = sg >= 0.0f ? 1.0f : -1.0f;
    }
    // The slice's line on the screen through the pixel: the image of P + t d, whose direction is
    // (d.x z - P.x d.z, -(d.y z - P.y d.z)) up to a positive factor (the slice plane contains the
    // eye, so its image is this line).
    precise float sx = d.x * p.z - p.x * d.z;
    precise float sy = p.y * d.z - d.y * p.z;
    precise float s_inv = 1.0f / sqrt(sx * sx + sy * sy);
    precise float ux = sx * s_inv;
    precise float uy = sy * s_inv;
    // The tangent-plane horizons, cos(gamma + pi/2) = -sg on the +d side and
    // cos(gamma - pi/2) = sg on the -d side: the clamp of eq. 8, the starting horizons.
    float low2 = -sg;
    float low1 = sg;
    float hc2 = low2;
    float hc1 = low1;
    for (int k = 0; k < c.steps; ++k) {
      // At least one pixel from the centre; then the sample distribution of the table (s^power).
      precise float off = 1.0f + gtao_step(GTAO_IMAGES_ARG i, j, k) * radius_px;
      precise float dx = ux * off;
      precise float dy = uy * off;
      hc2 = gtao_horizon_sample(GTAO_IMAGES_ARG px + dx, py + dy, p, v, low2, hc2, c);
      hc1 = gtao_horizon_sample(GTAO_IMAGES_ARG px - dx, py - dy, p, v, low1, hc1, c);
    }
    precise float sh2 = sqrt(max(1.0f - hc2 * hc2, 0.0f));
    precise float sh1 = -sqrt(max(1.0f - hc1 * hc1, 0.0f));
    precise float h2 = gtao_acos(hc2);
    precise float h1 = -gtao_acos(hc1);
    // The unoccluded slice through the same function, so that an open surface gives exactly 1.
    precise float o2 = gtao_acos(low2);
    precise float o1 = -gtao_acos(low1);
    precise float so = sqrt(max(1.0f - sg * sg, 0.0f));
    float a = gtao_slice_ao(hc1, sh1, h1, hc2, sh2, h2, cg, sg);
    float a_open = gtao_slice_ao(low1, -so, o1, low2, so, o2, cg, sg);
    vec2 b = gtao_slice_bent(hc1, sh1, hc2, sh2, cg, sg);
    precise float sum_new = sum + np_len * a;
    precise float open_new = open + np_len * a_open;
    precise vec3 bent_new = bent_sum + (d * b.x + v * b.y) * np_len;
    sum = sum_new;
    open = open_new;
    bent_sum = bent_new;
  }
  // normalise = 0: the paper's estimate (1/slices) sum |n_p| a. normalise = 1: divided by the
  // same sum over the unoccluded hemisphere (which tends to 1 with many slices), so that an open
  // surface is exactly 1 with any number of slices (our addition; see gtao.h).
  precise float plain = sum / float(c.slices);
  precise float ratio = sum / open;
  float ao = c.normalise != 0 ? (open > 0.0f ? ratio : 1.0f) : plain;
  precise float len = sqrt(gtao_dot(bent_sum, bent_sum));
  if (len > 0.0f) {
    precise vec3 unit = bent_sum / len;
    bent = unit;
  }
  return clamp(ao, 0.0f, 1.0f);
}

// The spatial denoise pass (the paper's §5.2: its noise repeats every 4 x 4 pixels and a 4 x 4
// bilateral filter averages one period of it): a tile x tile window (offsets -tile/2 ..
// tile - 1 - tile/2, so every texel of the noise texture enters once) over covered pixels, each
// weighted by the inverse of its depth deviation from the centre in pixel footprints at the
// centre's depth (z / f), offset by 1: w = 1 / (1 + |z - z_c| / (z_c / f)). The bent normal is the
// normalised weighted sum of the unit bent normals.
float gtao_denoise(GTAO_IMAGES_PARAM int i, int j, GtaoConstants c, GLSL_OUT(vec3) bent) {
  bent = vec3(0.0f, 0.0f, 0.0f);
  float zc = gtao_depth(GTAO_IMAGES_ARG i, j);
  if (!(zc > 0.0f)) return 0.0f;
  precise float footprint = zc / c.focal;
  precise float sum = 0.0f;
  precise float weights = 0.0f;
  precise vec3 bent_sum = vec3(0.0f, 0.0f, 0.0f);
  int lo = -(c.tile / 2);
  for (int dy = lo; dy < lo + c.tile; ++dy) {
    for (int dx = lo; dx < lo + c.tile; ++dx) {
      int x = i + dx;
      int y = j + dy;
      if (x < 0 || y < 0 || x >= c.width || y >= c.height) continue;
      float z = gtao_depth(GTAO_IMAGES_ARG x, y);
      if (!(z > 0.0f)) continue;
      precise float w = 1.0f / (1.0f + abs(z - zc) / footprint);
      sum = sum + w * gtao_raw_ao(GTAO_IMAGES_ARG x, y);
      weights = weights + w;
      bent_sum = bent_sum + gtao_raw_bent(GTAO_IMAGES_ARG x, y) * w;
    }
  }
  precise float len = sqrt(gtao_dot(bent_sum, bent_sum));
  if (len > 0.0f) {
    precise vec3 unit = bent_sum / len;
    bent = unit;
  }
  precise float ao = sum / weights;
  return ao;
}
