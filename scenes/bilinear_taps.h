// A bilinear read of an image at a continuous position, over a chosen set of its pixels: the four
// pixel centres around the position (pixel (i, j)'s centre at (i + 0.5, j + 0.5)), keeping those
// inside the image with a positive weight for which `valid(index)` holds. The weights are the
// bilinear ones, not renormalised; `total` is their sum, so a caller divides by it to average over
// the valid taps only. At an integer pixel offset one tap has weight 1 and the read is exact.
// Shared by the sequence scores (harness/scoring/temporal.cpp: frame k - 1 over its compared
// pixels) and the temporal accumulation stage (estimators/temporal/: the history over its valid
// texels), so both read the previous frame the same way.
#pragma once

#include <cmath>

namespace aoeval {

struct BilinearTaps {
  int index[4] = {0, 0, 0, 0};
  double weight[4] = {0.0, 0.0, 0.0, 0.0};
  int taps = 0;
  double total = 0.0;
};

template <class Valid>
BilinearTaps bilinear_taps(double x, double y, int w, int h, const Valid& valid) {
  BilinearTaps b;
  const double fx = x - 0.5, fy = y - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const double tx = fx - x0, ty = fy - y0;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const double wgt = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty);
      const double a = x0 + dx, c = y0 + dy;
      if (wgt <= 0.0 || a < 0.0 || c < 0.0 || a >= w || c >= h) continue;
      const int t = static_cast<int>(c) * w + static_cast<int>(a);
      if (!valid(t)) continue;
      b.index[b.taps] = t;
      b.weight[b.taps++] = wgt;
      b.total += wgt;
    }
  return b;
}

}  // namespace aoeval
