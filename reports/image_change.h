// Did the estimate itself move? (CONTRACT §12, issue 30.) Accuracy alone cannot say "the trees got
// darker": a biased-bright estimator that darkens everywhere may even lower its error. So the
// dashboard compares the new and the baseline estimate images of a matched row over the pixels
// both cover:
//   mean_shift      mean of (new - old) AO; negative = darker
//   changed_pixels  share of those pixels whose |new - old| exceeds what noise alone could make
// and calls the row CHANGED when |mean_shift| exceeds max(change_mean_shift, 4 sigma_mean).
//
// The noise the two images could differ by alone (`noise_rule`):
//   deterministic   the estimator has no `seed` parameter, or both rows used the same seed
//                   (CONTRACT: same seed, same bits): per pixel 1e-4 (float round-off of other
//                   compilers and drivers), sigma_mean = 0.
//   stderr          seeds differ and both images carry AO_stderr (the estimate's own per-pixel
//                   standard error, e.g. raytraced): |new - old| has standard deviation
//                   s_i = sqrt(se_new^2 + se_old^2); threshold 4 s_i + 1e-4 (two-sided Gaussian
//                   tail 6e-5 per pixel), sigma_mean = sqrt(sum s_i^2) / N (pixels draw their rays
//                   independently).
//   high-pass       seeds differ, no AO_stderr: the per-pixel noise is estimated from the
//                   difference image itself, sigma = 1.4826 median|L| / 6 with L the 3x3 Laplacian
//                   [1 -2 1; -2 4 -2; 1 -2 1] of (new - old) (Immerkaer 1996, "Fast noise
//                   variance estimation", CVIU 64(2); robust form): a smooth systematic change has
//                   almost no Laplacian while independent noise of sigma gives |L| of sigma * 6;
//                   but, per 8x8 tile, at least 1.4826 MAD of the tile's difference about its
//                   median, since noise correlated over a few pixels (blurred kernels) has little
//                   Laplacian and noise differs over the image (open areas have none); an uneven
//                   real change only raises it (changed_pixels then errs low). Threshold
//                   4 sigma + 1e-4 (pixel_threshold: the median over pixels). sigma_mean = sd(tile
//                   means) / sqrt(tiles) over 8x8 tiles: noise correlated over fewer than 8 pixels
//                   (screen-space kernels, rotation textures) averages out within a tile, and any
//                   uneven real change only raises the spread of the tile means, so the bound errs
//                   towards "unchanged". Not covered: a seed that moves the whole image coherently
//                   (shadowmap-ao's light set); raise change_mean_shift for such an estimator in
//                   the thresholds file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aoeval {

// The planes of an estimate EXR the dashboard reads (AO, coverage, optional AO_stderr).
struct AoPlanes {
  int w = 0, h = 0;
  std::vector<float> ao;
  std::vector<uint8_t> covered;
  std::vector<float> stderr_ao;  // empty when the image has no AO_stderr channel
};
// InputError naming the file when unreadable or without AO / A.
AoPlanes read_planes(const std::string& path);
// Mean AO over covered pixels; NaN when none is covered.
double mean_ao(const AoPlanes& p);

struct ImageChange {
  size_t pixels = 0;             // covered in both (and finite)
  double mean_shift = 0.0;       // mean(new - old)
  double changed_pixels = 0.0;   // share of `pixels` in [0, 1]
  double sigma_mean = 0.0;       // noise sigma of mean_shift (see above)
  double pixel_threshold = 0.0;  // the per-pixel threshold (median over pixels for "stderr")
  std::string noise_rule;        // "deterministic", "stderr", "high-pass"
};

// Compares two estimates of one point. `seeds_differ`: the estimator is stochastic and the rows
// used different seeds. std::invalid_argument when the sizes differ or no pixel is covered in both.
ImageChange compare_estimates(const AoPlanes& before, const AoPlanes& after, bool seeds_differ);

// The |mean_shift| a row must exceed to be CHANGED: max(change_mean_shift, 4 sigma_mean).
double change_threshold(const ImageChange& c, double change_mean_shift);

// The one line of a change: "darker by 0.050 mean AO on 97 % of pixels" (or "brighter").
std::string change_phrase(const ImageChange& c);

}  // namespace aoeval
