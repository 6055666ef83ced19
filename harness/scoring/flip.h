// LDR-FLIP for grey ambient-occlusion images, after
//   P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild,
//   "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact.
//   Tech. 3(2), 15:1-15:23 (HPG 2020).
// The pipeline, its constants and where each comes from are described in flip.cpp. What is ours:
//   * Input encoding: an AO value is a *linear* luminance. It is clamped to [0, 1] (what a display
//     can show), sRGB-encoded to a display value, and that display value is FLIP's sRGB input.
//     FLIP decodes it back to linear RGB, so the grey linear RGB FLIP works on is clamp(AO, 0, 1).
//   * Masking: only compared pixels (mask nonzero) contribute to any filter. Every filter is a
//     normalised convolution: the CSF filter's weights are renormalised over compared pixels, and
//     the positive and negative lobes of each feature filter are renormalised separately (each to
//     +1 / -1) over compared pixels; a lobe with no compared pixel gives a zero response. With
//     every pixel compared this is exactly the paper's filtering with the reference code's
//     edge-replicating border ("clamp to border").
//   * The map is 0 at pixels that are not compared.
#pragma once

#include <cstdint>
#include <vector>

namespace aoeval {

namespace flip {

// Pixels per degree of visual angle for an observer `distance_m` from a monitor `width_m` wide
// with `pixels_x` pixels across. FLIP's default viewing condition (0.7 m, 0.7 m, 3840 pixels)
// gives 67.02 pixels per degree.
double pixels_per_degree(double distance_m = 0.7, double width_m = 0.7, double pixels_x = 3840.0);

// Per-pixel LDR-FLIP error in [0, 1] of `est` against `ref` (both width*height, row-major, linear
// AO values), over the compared pixels of `mask` (width*height, nonzero = compared). Values of
// pixels that are not compared are never read (they may be NaN). Inputs must be finite at compared
// pixels; the caller checks.
std::vector<float> error_map(int width, int height, const float* ref, const float* est,
                             const uint8_t* mask, double ppd = pixels_per_degree());

// The part of the map that depends on the reference and the mask only (its filtered channel and
// feature responses, the mask's filter weights), computed once for every estimate scored against
// one reference: error_map(prepare_reference(w, h, ref, mask, ppd), est) is the same bits as
// error_map(w, h, ref, est, mask, ppd), at about a third of the filtering per estimate.
struct ReferenceSide {
  int width = 0, height = 0;
  double ppd = 0.0;
  std::vector<uint8_t> mask;
  std::vector<double> wsum, filtered;       // CSF-filtered mask and reference
  std::vector<double> mask_lobes[2][2][2];  // [x, y][edges, points][positive, negative]
  std::vector<double> squared[2];           // the reference's squared responses [edges, points]
};
ReferenceSide prepare_reference(int width, int height, const float* ref, const uint8_t* mask,
                                double ppd = pixels_per_degree());
std::vector<float> error_map(const ReferenceSide& reference, const float* est);

}  // namespace flip

namespace detail {

// Separable filtering helpers shared by SSIM and FLIP. `kernel` has odd length 2r+1 and is
// applied as a correlation: out(x) = sum_k kernel[k + r] * in(x + k). Outside the image, kZero
// reads 0 and kClamp reads the nearest edge pixel. Rows are processed in parallel; every output
// value is computed by the same sequence of operations whatever the scheduling.
enum class Border { kZero, kClamp };
std::vector<double> filter_rows(const std::vector<double>& in, int width, int height,
                                const std::vector<double>& kernel, Border border);
std::vector<double> filter_cols(const std::vector<double>& in, int width, int height,
                                const std::vector<double>& kernel, Border border);
// The same, writing into `out` (resized to in.size()) so that buffers can be reused.
void filter_rows(const std::vector<double>& in, int width, int height,
                 const std::vector<double>& kernel, Border border, std::vector<double>& out);
void filter_cols(const std::vector<double>& in, int width, int height,
                 const std::vector<double>& kernel, Border border, std::vector<double>& out);

}  // namespace detail

}  // namespace aoeval
