// Image-comparison metrics of `aoeval compare` and of every results row (CONTRACT §3-4), computed
// over the *compared pixels*: those where both images have coverage A = 1 and, optionally, a
// further mask holds. The caller builds that mask; this file scores two float AO images under it.
//
// Definitions (n = number of compared pixels, d = est - ref per compared pixel, in double):
//   pixels          n
//   rmse            sqrt(mean d^2)
//   mae             mean |d|
//   bias            mean d
//   max_abs         max |d|
//   p95_abs         95th percentile of |d| by nearest rank: the k-th smallest |d| with
//                   k = ceil(0.95 n) (1-based), so always one of the observed values
//   median_abs      the median of |d| by the same nearest-rank rule, k = ceil(0.5 n): the typical
//                   pixel's error, which a few bad pixels (a halo) do not move, unlike mae
//   psnr            peak 1: 10 log10(1 / mean d^2); +infinity when mean d^2 = 0, written as JSON
//                   null (JSON has no infinity)
//   ssim            Wang, Bovik, Sheikh, Simoncelli, "Image Quality Assessment: From Error
//                   Visibility to Structural Similarity", IEEE TIP 13(4), 2004: eq. 13 (SSIM with
//                   C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 1), local statistics under the 11x11
//                   circular-symmetric Gaussian window with sigma 1.5 (eq. 14-16), pooled by the
//                   mean of the SSIM map (eq. 17). Masked: each window's Gaussian weights are
//                   renormalised over the compared pixels inside it (pixels outside the image count
//                   as not compared) and the map is averaged over compared pixels. No dynamic-
//                   range clamping: AO values enter as they are.
//   flip_mean       mean over compared pixels of the LDR-FLIP map (Andersson et al. 2020) of the
//                   AO images seen as grey, AO = linear luminance; see flip.h/flip.cpp
//   ref_stderr_rms  sqrt(mean ref_stderr^2) (0 when the reference has no stderr channel)
//   rmse_excess     sqrt(max(0, rmse^2 - mean ref_stderr^2)): the error left once the
//                   reference's own Monte Carlo noise is accounted for
//   rmse_excess_sd  the standard deviation of rmse_excess that the reference's noise causes (what
//                   its spp buys; README "How precise a reference must be"). With d_i = est - ref
//                   and s_i the stderr at compared pixel i, rmse_excess^2 is an unbiased estimate
//                   of mean (est - truth)^2 whose variance over the reference's noise (independent
//                   per pixel, near normal) is V = (4 sum_i t_i s_i^2 + 2 sum_i s_i^4) / N^2,
//                   t_i = (est - truth)_i^2, estimated without bias by d_i^2 - s_i^2 (the sum of
//                   those terms clamped at 0). By the delta method rmse_excess_sd = sqrt(V) /
//                   (2 rmse_excess), and at most V^(1/4), the spread of a root near 0. Where the
//                   error sits where the reference is noisy (creases; a bounded definition's open
//                   pixels have none) sum t_i s_i^2 exceeds rmse_excess^2 sum s_i^2, measured up
//                   to 4.9x on the default suite's views: a rule from the row's rms values alone
//                   understates the spread there. 0 without a stderr channel.
// Every sum is accumulated in double per image row, and the rows are added in order, so the
// results do not depend on thread scheduling.
#pragma once

#include "harness/scoring/flip.h"

#include <cstddef>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace aoeval {

struct Metrics {
  size_t pixels;
  double rmse, mae, bias, max_abs, p95_abs, median_abs, psnr, ssim, flip_mean, ref_stderr_rms,
      rmse_excess, rmse_excess_sd;
};

// A plain float image, row-major, width * height values; row 0 is the top, pixel (i, j) is column
// i of row j.
// rmse_excess_sd's rule: the spread of sqrt(max(0, X)) where X estimates D^2 = `excess`^2 with
// variance `variance` (0 when `variance` <= 0).
double excess_sd(double excess, double variance);

struct ImageView {
  int width, height;
  const float* data;
};

// Scores `est` against `ref` over the pixels where `mask` is nonzero (`mask` empty: every pixel).
// `ref_stderr` is the reference's per-pixel standard error, or empty (treated as 0).
// Throws InputError (base/errors.h) when the sizes differ (naming both), when the mask or the
// stderr has the wrong size, when no pixel is compared ("no pixel is covered in both images"),
// and when a compared pixel of either image (or of ref_stderr) is NaN or infinite (naming the
// image and the pixel (i, j)).
// `flip_reference`, when given, is FLIP's reference side prepared for this reference and mask
// (flip::prepare_reference), reused across the estimates scored against one reference; one
// prepared for another mask or size is not used.
Metrics compare_images(ImageView ref, ImageView est, const std::vector<uint8_t>& mask,
                       const std::vector<float>& ref_stderr,
                       const flip::ReferenceSide* flip_reference = nullptr);

// The metrics as a JSON object, keys exactly metric_keys() with `prefix` before each (e.g.
// "true_"). `pixels` is an integer; psnr (or any other non-finite value) is null.
nlohmann::json to_json(const Metrics& m, const std::string& prefix = "");

// The image keys of the metric table (harness/results/metric_table.h), in its order.
std::vector<std::string> metric_keys();

// The per-pixel maps behind ssim and flip_mean (width * height, 0 at pixels not compared). Same
// checks and errors as compare_images.
std::vector<float> ssim_map(ImageView ref, ImageView est, const std::vector<uint8_t>& mask);
std::vector<float> flip_map(ImageView ref, ImageView est, const std::vector<uint8_t>& mask);

}  // namespace aoeval
