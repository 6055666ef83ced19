// Half resolution, shared by hbao-split and gtao and by both twins of each (the CPU compiles this
// text as C++ through glsl_compat.h, the upsample shaders as GLSL): which half-resolution samples
// surround a full-resolution pixel, and the joint bilateral weights that upsample an image computed
// at half resolution (Kopf et al. 2007, "Joint Bilateral Upsampling": a low-resolution solution
// upsampled with a spatial filter on the low-resolution grid times a range filter on the
// high-resolution guide, here the G-buffer's depth and normal).
//
// Downsampling (half_res.h, half_res_down.comp): half-resolution pixel (i, j) IS full-resolution
// pixel (2i, 2j), the top-left of its 2 x 2 block, with its own depth and normal. Not the nearest
// (or an averaged) depth: a fixed sample keeps the half-resolution frame a regular pinhole image
// (focal f / 2, principal point shifted by a quarter pixel, half_res.h), so the kernels rebuild
// every sample's eye position exactly, a plane stays a plane, and the upsample knows where each
// sample lies; a nearest-depth pick would move samples by up to a pixel in ways the kernels cannot
// see and would always favour foreground at edges. The cost: a feature narrower than two pixels
// can fall between samples (the half-resolution figure's edge pixels measure it).
//
// Upsampling, full-resolution pixel p = (x, y) with depth z_p > 0 and eye normal n_p:
//   candidates  the half-resolution samples k at (x / 2 or (x + 1) / 2, y / 2 or (y + 1) / 2),
//               integer division, clamped to the half frame: the 1, 2 or 4 samples whose
//               full-resolution pixels are nearest to p (p itself when x and y are even);
//   w_k = b_k * w_z * w_n  with
//     b_k  the bilinear weight on the half-resolution grid: 1 or 1/2 per axis (1/2 each for an odd
//          coordinate, all on the first sample for an even one);
//     w_z  = max(0, 1 - |z_k - z_p| / (kHalfResDepthTolerance z_p)), a tent on the relative depth
//          difference (0 for a sample 5 % or more of z_p nearer or farther: across a depth
//          discontinuity nothing bleeds, while a floor seen 85 degrees from its normal changes depth
//          by under 2 % from one pixel to the next, 1/f tan(85 deg) at f ~ 290 pixels);
//     w_n  = max(0, n_p . n_k)^8 (0 across a crease of 90 degrees or more; cos 30 deg^8 = 0.32);
//   AO_p = sum_k w_k AO_k / sum_k w_k when sum_k w_k > kHalfResMinWeight; otherwise (every
//   candidate rejected: a pixel on a feature the half frame missed) the candidate nearest in depth
//   among the covered ones with b_k > 0 alone; with none covered, AO_p = 1 (nothing seen around p
//   can occlude it) and the vector 0. Uncovered pixels (z_p = 0) stay 0.
// Only + - * / comparisons and max: both twins compute the same bits where the device rounds as
// IEEE 754 does (the twin tests).

// The accessors the includer defines: halfres_depth(i, j) and halfres_normal(i, j) read the
// FULL-resolution frame (linear depth, 0 = background; unit eye-space normal).

const float kHalfResDepthTolerance = 0.05f;
const float kHalfResMinWeight = 1.0e-3f;

// Candidate k (0..3: bit 0 the second column, bit 1 the second row), a half-resolution pixel.
ivec2 halfres_candidate(int x, int y, int k, HalfResConstants c) {
  int i = (k & 1) != 0 ? min((x + 1) / 2, c.low_width - 1) : x / 2;
  int j = (k & 2) != 0 ? min((y + 1) / 2, c.low_height - 1) : y / 2;
  return ivec2(i, j);
}

// The four candidates' normalised weights (half_res.glsl's header); all 0 with no covered
// candidate. Callers skip p when its own depth is 0.
vec4 halfres_weights(HALFRES_IMAGES_PARAM int x, int y, HalfResConstants c) {
  precise float zp = halfres_depth(HALFRES_IMAGES_ARG x, y);
  vec3 np = halfres_normal(HALFRES_IMAGES_ARG x, y);
  float bx = (x & 1) != 0 ? 0.5f : 0.0f;  // the second column's bilinear weight
  float by = (y & 1) != 0 ? 0.5f : 0.0f;
  vec4 w = vec4(0.0f);
  precise float sum = 0.0f;
  int best = -1;
  precise float best_dz = 0.0f;
  for (int k = 0; k < 4; ++k) {
    ivec2 s = halfres_candidate(x, y, k, c);
    precise float zk = halfres_depth(HALFRES_IMAGES_ARG 2 * s.x, 2 * s.y);
    vec3 nk = halfres_normal(HALFRES_IMAGES_ARG 2 * s.x, 2 * s.y);
    precise float b = ((k & 1) != 0 ? bx : 1.0f - bx) * ((k & 2) != 0 ? by : 1.0f - by);
    if (!(zk > 0.0f) || !(b > 0.0f)) continue;
    precise float dz = abs(zk - zp);
    precise float wz = max(0.0f, 1.0f - dz / (kHalfResDepthTolerance * zp));
    precise float cn = max(0.0f, np.x * nk.x + np.y * nk.y + np.z * nk.z);
    precise float cn2 = cn * cn;
    precise float cn4 = cn2 * cn2;
    precise float wk = b * wz * (cn4 * cn4);
    w[k] = wk;
    sum += wk;
    if (best < 0 || dz < best_dz) {
      best = k;
      best_dz = dz;
    }
  }
  if (sum > kHalfResMinWeight) {
    precise float inv = 1.0f / sum;
    return vec4(w.x * inv, w.y * inv, w.z * inv, w.w * inv);
  }
  vec4 one = vec4(0.0f);
  if (best >= 0) one[best] = 1.0f;
  return one;
}
