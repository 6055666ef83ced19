// Image-comparison metrics; definitions in metrics.h. SSIM follows Wang et al. 2004 (IEEE TIP
// 13(4)): eq. 13 with C1 = (K1 L)^2, C2 = (K2 L)^2, K1 = 0.01, K2 = 0.03 (eq. 7 and 9), Gaussian-
// weighted local statistics eq. 14-16 (11x11 window, sigma 1.5, §III.B) and mean pooling eq. 17,
// made masked by renormalising the window weights over compared pixels. FLIP is in flip.cpp.
#include "harness/scoring/metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "harness/results/metric_table.h"
#include "harness/scoring/flip.h"
#include "harness/scoring/side_by_side.h"

namespace aoeval {

namespace {

using detail::Border;
using detail::filter_cols;
using detail::filter_rows;

std::string size_text(ImageView v) {
  return std::to_string(v.width) + "x" + std::to_string(v.height);
}

void check_value(float v, const char* what, int i, int j) {
  if (std::isnan(v))
    throw InputError(std::string("NaN in the ") + what + " at pixel (" + std::to_string(i) + ", " +
                     std::to_string(j) + ")");
  if (std::isinf(v))
    throw InputError(std::string("infinite value in the ") + what + " at pixel (" +
                     std::to_string(i) + ", " + std::to_string(j) + ")");
}

// Checks sizes and values; returns the effective mask (every pixel when `mask` is empty).
std::vector<uint8_t> validate(ImageView ref, ImageView est, const std::vector<uint8_t>& mask,
                              const std::vector<float>* ref_stderr) {
  if (ref.width != est.width || ref.height != est.height)
    throw InputError("image sizes differ: reference is " + size_text(ref) + ", estimate is " +
                     size_text(est));
  if (ref.width < 0 || ref.height < 0) throw InputError("invalid image size " + size_text(ref));
  const size_t n = static_cast<size_t>(ref.width) * static_cast<size_t>(ref.height);
  if (n > 0 && (ref.data == nullptr || est.data == nullptr))
    throw InputError("image of size " + size_text(ref) + " has no pixel data");
  if (!mask.empty() && mask.size() != n)
    throw InputError("mask has " + std::to_string(mask.size()) + " values, images are " +
                     size_text(ref));
  if (ref_stderr && !ref_stderr->empty() && ref_stderr->size() != n)
    throw InputError("reference AO_stderr has " + std::to_string(ref_stderr->size()) +
                     " values, images are " + size_text(ref));
  std::vector<uint8_t> m = mask.empty() ? std::vector<uint8_t>(n, 1) : mask;
  size_t count = 0;
  for (int j = 0; j < ref.height; ++j) {
    for (int i = 0; i < ref.width; ++i) {
      const size_t p = static_cast<size_t>(j) * ref.width + i;
      if (!m[p]) continue;
      m[p] = 1;
      ++count;
      check_value(ref.data[p], "reference", i, j);
      check_value(est.data[p], "estimate", i, j);
      if (ref_stderr && !ref_stderr->empty())
        check_value((*ref_stderr)[p], "reference AO_stderr", i, j);
    }
  }
  if (count == 0) throw InputError("no pixel is covered in both images");
  return m;
}

template <class Fn>
void for_rows(int height, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) fn(y);
  });
}

// Mean of `map` over the mask: per-row sums, rows added in order.
double masked_mean(const std::vector<float>& map, const std::vector<uint8_t>& m, int width,
                   int height) {
  std::vector<double> rows(height, 0.0);
  std::vector<size_t> counts(height, 0);
  for_rows(height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y) * width + x;
      if (!m[p]) continue;
      rows[y] += map[p];
      ++counts[y];
    }
  });
  double sum = 0.0;
  size_t count = 0;
  for (int y = 0; y < height; ++y) {
    sum += rows[y];
    count += counts[y];
  }
  return sum / static_cast<double>(count);
}

std::vector<float> ssim_map_checked(ImageView ref, ImageView est, const std::vector<uint8_t>& m) {
  const int w = ref.width, h = ref.height;
  const size_t n = m.size();
  constexpr int kRadius = 5;  // 11x11 window
  constexpr double kSigma = 1.5;
  constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;  // L = 1
  std::vector<double> g(2 * kRadius + 1);
  double gsum = 0.0;
  for (int i = -kRadius; i <= kRadius; ++i)
    gsum += g[i + kRadius] = std::exp(-i * i / (2 * kSigma * kSigma));
  for (double& v : g) v /= gsum;

  // Masked moments: m, m x, m y, m x^2, m y^2, m x y (x = ref, y = est).
  std::vector<double> ch[6];
  for (auto& c : ch) c.assign(n, 0.0);
  for (size_t p = 0; p < n; ++p) {
    if (!m[p]) continue;
    const double x = ref.data[p], y = est.data[p];
    ch[0][p] = 1.0;
    ch[1][p] = x;
    ch[2][p] = y;
    ch[3][p] = x * x;
    ch[4][p] = y * y;
    ch[5][p] = x * y;
  }
  std::vector<double> tmp;
  for (auto& c : ch) {
    filter_rows(c, w, h, g, Border::kZero, tmp);
    filter_cols(tmp, w, h, g, Border::kZero, c);
  }

  std::vector<float> out(n, 0.0f);
  for_rows(h, [&](int yrow) {
    for (int xcol = 0; xcol < w; ++xcol) {
      const size_t p = static_cast<size_t>(yrow) * w + xcol;
      if (!m[p]) continue;
      const double wsum = ch[0][p];  // > 0: the pixel itself is compared
      const double mx = ch[1][p] / wsum, my = ch[2][p] / wsum;
      // Not clamped at 0: identical images then give exactly 1, and C2 dwarfs rounding.
      const double vx = ch[3][p] / wsum - mx * mx, vy = ch[4][p] / wsum - my * my;
      const double cxy = ch[5][p] / wsum - mx * my;
      out[p] = static_cast<float>(((2 * mx * my + kC1) * (2 * cxy + kC2)) /
                                  ((mx * mx + my * my + kC1) * (vx + vy + kC2)));
    }
  });
  return out;
}

}  // namespace

double excess_sd(double excess, double variance) {
  if (!(variance > 0.0)) return 0.0;
  const double near_zero = std::pow(variance, 0.25);
  return excess > 0.0 ? std::min(near_zero, std::sqrt(variance) / (2.0 * excess)) : near_zero;
}

std::vector<std::string> metric_keys() {
  return metric_keys_of(MetricFamily::image);
}

nlohmann::json to_json(const Metrics& m, const std::string& prefix) {
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{prefix + "pixels", static_cast<uint64_t>(m.pixels)},
          {prefix + "rmse", num(m.rmse)},
          {prefix + "mae", num(m.mae)},
          {prefix + "bias", num(m.bias)},
          {prefix + "max_abs", num(m.max_abs)},
          {prefix + "p95_abs", num(m.p95_abs)},
          {prefix + "median_abs", num(m.median_abs)},
          {prefix + "psnr", num(m.psnr)},
          {prefix + "ssim", num(m.ssim)},
          {prefix + "flip_mean", num(m.flip_mean)},
          {prefix + "ref_stderr_rms", num(m.ref_stderr_rms)},
          {prefix + "rmse_excess", num(m.rmse_excess)},
          {prefix + "rmse_excess_sd", num(m.rmse_excess_sd)}};
}

std::vector<float> ssim_map(ImageView ref, ImageView est, const std::vector<uint8_t>& mask) {
  return ssim_map_checked(ref, est, validate(ref, est, mask, nullptr));
}

std::vector<float> flip_map(ImageView ref, ImageView est, const std::vector<uint8_t>& mask) {
  const std::vector<uint8_t> m = validate(ref, est, mask, nullptr);
  return flip::error_map(ref.width, ref.height, ref.data, est.data, m.data());
}

namespace {
// n, rmse, mae, bias, max_abs, p95_abs, median_abs, psnr, ref_stderr_rms and rmse_excess into
// `out`.
void error_statistics(ImageView ref, ImageView est, const std::vector<uint8_t>& m,
                      const std::vector<float>& ref_stderr, Metrics& out);
}  // namespace

Metrics compare_images(ImageView ref, ImageView est, const std::vector<uint8_t>& mask,
                       const std::vector<float>& ref_stderr,
                       const flip::ReferenceSide* flip_reference) {
  const std::vector<uint8_t> m = validate(ref, est, mask, &ref_stderr);
  const int w = ref.width, h = ref.height;
  // SSIM, FLIP and the error statistics are independent: computed side by side (issue 42: on the
  // background lane a scoring ran on one core while the runner waited for it; side_by_side.h),
  // each exactly as alone (the same bits).
  Metrics out{};
  const bool prepared = flip_reference && flip_reference->width == w &&
                        flip_reference->height == h && flip_reference->mask == m;
  detail::side_by_side([&] { out.ssim = masked_mean(ssim_map_checked(ref, est, m), m, w, h); },
                       [&] {
                         out.flip_mean = masked_mean(
                             prepared ? flip::error_map(*flip_reference, est.data)
                                      : flip::error_map(w, h, ref.data, est.data, m.data()),
                             m, w, h);
                       },
                       [&] { error_statistics(ref, est, m, ref_stderr, out); });
  return out;
}

namespace {

void error_statistics(ImageView ref, ImageView est, const std::vector<uint8_t>& m,
                      const std::vector<float>& ref_stderr, Metrics& out) {
  const int w = ref.width, h = ref.height;
  const bool has_stderr = !ref_stderr.empty();
  struct Row {
    size_t n = 0;
    double sum = 0, sum_abs = 0, sum_sq = 0, max_abs = 0, sum_var = 0;
    double sum_cross = 0, sum_var2 = 0;  // rmse_excess_sd's sums of (d^2 - s^2) s^2 and s^4
  };
  std::vector<Row> rows(h);
  for_rows(h, [&](int y) {
    Row& r = rows[y];
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (!m[p]) continue;
      const double d = static_cast<double>(est.data[p]) - static_cast<double>(ref.data[p]);
      ++r.n;
      r.sum += d;
      r.sum_abs += std::abs(d);
      r.sum_sq += d * d;
      r.max_abs = std::max(r.max_abs, std::abs(d));
      if (has_stderr) {
        const double var = static_cast<double>(ref_stderr[p]) * ref_stderr[p];
        r.sum_var += var;
        r.sum_cross += (d * d - var) * var;
        r.sum_var2 += var * var;
      }
    }
  });
  Row total;
  std::vector<size_t> offset(h + 1, 0);
  for (int y = 0; y < h; ++y) {
    total.n += rows[y].n;
    total.sum += rows[y].sum;
    total.sum_abs += rows[y].sum_abs;
    total.sum_sq += rows[y].sum_sq;
    total.max_abs = std::max(total.max_abs, rows[y].max_abs);
    total.sum_var += rows[y].sum_var;
    total.sum_cross += rows[y].sum_cross;
    total.sum_var2 += rows[y].sum_var2;
    offset[y + 1] = offset[y] + rows[y].n;
  }

  // p95_abs by nearest rank: the k-th smallest |d|, k = ceil(0.95 n).
  std::vector<double> abs_d(total.n);
  for_rows(h, [&](int y) {
    size_t k = offset[y];
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (m[p]) abs_d[k++] = std::abs(static_cast<double>(est.data[p]) - ref.data[p]);
    }
  });
  const size_t rank = (95 * total.n + 99) / 100;  // ceil(0.95 n), >= 1
  std::nth_element(abs_d.begin(), abs_d.begin() + (rank - 1), abs_d.end());
  const double p95_abs = abs_d[rank - 1];
  // median_abs by the same rule, k = ceil(0.5 n) <= the p95 rank: among the values below it.
  const size_t median_rank = (total.n + 1) / 2;
  std::nth_element(abs_d.begin(), abs_d.begin() + (median_rank - 1), abs_d.begin() + rank);

  const double count = static_cast<double>(total.n);
  const double mse = total.sum_sq / count;
  const double mean_var = total.sum_var / count;
  out.pixels = total.n;
  out.rmse = std::sqrt(mse);
  out.mae = total.sum_abs / count;
  out.bias = total.sum / count;
  out.max_abs = total.max_abs;
  out.p95_abs = p95_abs;
  out.median_abs = abs_d[median_rank - 1];
  out.psnr = mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
  out.ref_stderr_rms = std::sqrt(mean_var);
  out.rmse_excess = std::sqrt(std::max(0.0, mse - mean_var));
  out.rmse_excess_sd =
      excess_sd(out.rmse_excess,
                (4.0 * std::max(0.0, total.sum_cross) + 2.0 * total.sum_var2) / (count * count));
}

}  // namespace

}  // namespace aoeval
