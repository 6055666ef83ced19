// The spatial half of SVGF (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering:
// Real-Time Reconstruction for Path-Traced Global Illumination", HPG 2017) for a scalar signal
// (AO, whose "luminance" is itself), after the shared temporal stage (estimators/temporal/) has
// accumulated the value and its first two moments:
//
//  - Variance estimation (§4.2): where a pixel's history is at least `variance_frames` long
//    (the paper's 4), sigma^2 = max(0, m2 - m1^2) from its temporally accumulated moments; where it
//    is shorter, the moments are averaged first over a (2 variance_radius + 1)^2 bilateral
//    neighbourhood (the paper's 7x7: radius 3) with the depth
//    and normal weights w_z w_n below ("we estimate the variance spatially using a 7x7 bilateral
//    filter with weights driven by depth and world-space normals").
//  - Edge-avoiding a-trous wavelet transform (§4.3, after Dammertz et al. 2010): iteration i
//    filters with the 5x5 B3-spline kernel h = (1/16, 1/4, 3/8, 1/4, 1/16)^2, its taps 2^i pixels
//    apart,
//        c_{i+1}(p) = sum_q h(q) w_i(p, q) c_i(q) / sum_q h(q) w_i(p, q)                   (eq. 1)
//    and the variance with the squared weights,
//        Var_{i+1}(p) = sum_q h(q)^2 w_i(p, q)^2 Var_i(q) / (sum_q h(q) w_i(p, q))^2        (eq. 2)
//  - Edge-stopping functions (§4.4), w_i = w_z w_n w_l:
//        w_z = exp(-|z(p) - z(q)| / (sigma_z |grad z(p) . (p - q)| + eps))                 (eq. 3)
//        w_n = max(0, n(p) . n(q))^sigma_n                                                 (eq. 4)
//        w_l = exp(-|l_i(p) - l_i(q)| / (sigma_l sqrt(g_3x3(Var_i(l_i(p)))) + eps))          (eq.
//        5)
//    with z the G-buffer's linear depth, grad z its screen-space gradient (central differences
//    over covered pixels), n the shading normal and g_3x3 a 3x3 Gaussian of the variance. eps is a
//    numerical guard only (1e-6 of the pixel's depth in eq. 3, 1e-10 in eq. 5), not a setting.
// Only covered pixels filter and are filtered. CPU: the G-buffer's channels read once per frame
// into one array each (SvgfGuide), then row tiles in parallel with TBB, each tap of the kernel (or
// a kernel row's five) a vectorised loop along the row (svgf_math.h's exp and log, within 2 ulp of
// libm), compiled for SSE2, AVX2 and AVX-512 and run in the widest the CPU has (svgf_taps.h).
// Every pixel sums its taps in the kernel's order whatever the tiling and instruction set: the
// same bits for any thread count and CPU (svgf_test).
#pragma once

#include <vector>

#include "scenes/gbuffer.h"

namespace aoeval {

struct SvgfSettings {
  double sigma_z = 0.0, sigma_n = 0.0, sigma_l = 0.0;  // eqs. 3-5
  int variance_frames = 0;                             // §4.2: temporal variance from this many
  int variance_radius = 0;                             // §4.2: the spatial estimate's half-width
};

// What the edge-stopping weights read of the G-buffer, one array per channel: the shading normal,
// the linear depth, its screen-space gradient (central differences over covered pixels, pixels per
// unit step in x and y) and the coverage (1 or 0).
struct SvgfGuide {
  int width = 0, height = 0;
  std::vector<float> nx, ny, nz, depth, grad_x, grad_y, covered;
};
SvgfGuide svgf_guide(const GBuffer& g);
// The same into `out`, reusing its arrays (no allocation when the size is unchanged).
void svgf_guide(const GBuffer& g, SvgfGuide& out);

// §4.2: the variance of each covered pixel from its moments and history length.
std::vector<float> svgf_variance(const SvgfGuide& g, const std::vector<float>& moment1,
                                 const std::vector<float>& moment2,
                                 const std::vector<float>& history_length, const SvgfSettings& s);

// One a-trous iteration (eqs. 1-5) with taps `step` pixels apart: filters `value` and `variance`
// in place.
void atrous_iteration(const SvgfGuide& g, int step, const SvgfSettings& s,
                      std::vector<float>& value, std::vector<float>& variance);

}  // namespace aoeval
