// Changes of an estimate against its baseline (see image_change.h for the noise rules).
#include "reports/image_change.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "scenes/ao_exr.h"

namespace aoeval {

namespace {

constexpr double kRoundOff = 1e-4;  // CONTRACT §12: deterministic estimators
constexpr double kSigmas = 4.0;     // per-pixel and mean-shift noise multiples
constexpr int kTile = 8;            // high-pass rule: tile side for sigma_mean, pixels

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  return v[mid];
}

}  // namespace

AoPlanes read_planes(const std::string& path) {
  AoExr f = read_ao_exr(path);
  AoPlanes p;
  p.w = f.width;
  p.h = f.height;
  p.ao = std::move(f.ao);
  p.stderr_ao = std::move(f.stderr_ao);
  p.covered.resize(f.coverage.size());
  for (size_t k = 0; k < f.coverage.size(); ++k) p.covered[k] = f.covered(k);
  return p;
}

double mean_ao(const AoPlanes& p) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < p.ao.size(); ++k)
    if (p.covered[k] && std::isfinite(p.ao[k])) {
      sum += p.ao[k];
      ++n;
    }
  return n ? sum / static_cast<double>(n) : std::nan("");
}

ImageChange compare_estimates(const AoPlanes& b, const AoPlanes& a, bool seeds_differ) {
  if (b.w != a.w || b.h != a.h)
    throw std::invalid_argument("the estimates differ in size (" + std::to_string(b.w) + "x" +
                                std::to_string(b.h) + " and " + std::to_string(a.w) + "x" +
                                std::to_string(a.h) + ")");
  const size_t n = static_cast<size_t>(a.w) * static_cast<size_t>(a.h);
  std::vector<uint8_t> both(n, 0);
  std::vector<double> diff(n, 0.0);
  ImageChange c;
  double sum = 0.0;
  for (size_t k = 0; k < n; ++k) {
    diff[k] = static_cast<double>(a.ao[k]) - b.ao[k];
    both[k] = b.covered[k] && a.covered[k] && std::isfinite(diff[k]);
    if (!both[k]) continue;
    sum += diff[k];
    ++c.pixels;
  }
  if (c.pixels == 0) throw std::invalid_argument("no pixel is covered in both estimates");
  const double count = static_cast<double>(c.pixels);
  c.mean_shift = sum / count;

  // Per-pixel thresholds by rule.
  std::vector<double> threshold(n, kRoundOff);
  const bool with_stderr = seeds_differ && b.stderr_ao.size() == n && a.stderr_ao.size() == n;
  if (!seeds_differ) {
    c.noise_rule = "deterministic";
  } else if (with_stderr) {
    c.noise_rule = "stderr";
    double var_sum = 0.0;
    std::vector<double> used;
    for (size_t k = 0; k < n; ++k) {
      if (!both[k]) continue;
      const double v = static_cast<double>(a.stderr_ao[k]) * a.stderr_ao[k] +
                       static_cast<double>(b.stderr_ao[k]) * b.stderr_ao[k];
      var_sum += v;
      threshold[k] = kSigmas * std::sqrt(v) + kRoundOff;
      used.push_back(threshold[k]);
    }
    c.sigma_mean = std::sqrt(var_sum) / count;
    c.pixel_threshold = median_of(used);
  } else {
    c.noise_rule = "high-pass";
    // Immerkaer's mask on the difference, where the whole 3x3 neighbourhood is compared.
    std::vector<double> laplacian;
    for (int y = 1; y + 1 < a.h; ++y)
      for (int x = 1; x + 1 < a.w; ++x) {
        double l = 0.0;
        bool ok = true;
        for (int dy = -1; dy <= 1 && ok; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const size_t k = static_cast<size_t>(y + dy) * a.w + (x + dx);
            if (!both[k]) {
              ok = false;
              break;
            }
            const double m = (dx == 0 ? 2.0 : -1.0) * (dy == 0 ? 2.0 : -1.0);  // [1 -2 1]^T[1 -2 1]
            l += m * diff[k];
          }
        if (ok) laplacian.push_back(std::abs(l));
      }
    const double laplacian_sigma = 1.4826 * median_of(laplacian) / 6.0;
    // Noise correlated over a few pixels (blurred screen-space kernels) has little Laplacian, and
    // its size varies over the image (open areas have none): per 8x8 tile, the difference's own
    // robust spread (MAD about the tile's median) is the floor; a real uneven change only raises
    // it (conservative).
    std::vector<double> used;
    for (int ty = 0; ty < a.h; ty += kTile)
      for (int tx = 0; tx < a.w; tx += kTile) {
        std::vector<size_t> members;
        for (int y = ty; y < std::min(a.h, ty + kTile); ++y)
          for (int x = tx; x < std::min(a.w, tx + kTile); ++x) {
            const size_t k = static_cast<size_t>(y) * a.w + x;
            if (both[k]) members.push_back(k);
          }
        if (members.empty()) continue;
        std::vector<double> values;
        for (size_t k : members) values.push_back(diff[k]);
        const double centre = median_of(values);
        for (double& v : values) v = std::abs(v - centre);
        const double sigma = std::max(laplacian_sigma, 1.4826 * median_of(values));
        for (size_t k : members) {
          threshold[k] = kSigmas * sigma + kRoundOff;
          used.push_back(threshold[k]);
        }
      }
    c.pixel_threshold = median_of(used);
    // sigma_mean from the spread of 8x8 tile means (image_change.h).
    std::vector<double> tiles;
    for (int ty = 0; ty < a.h; ty += kTile)
      for (int tx = 0; tx < a.w; tx += kTile) {
        double s = 0.0;
        int m = 0;
        for (int y = ty; y < std::min(a.h, ty + kTile); ++y)
          for (int x = tx; x < std::min(a.w, tx + kTile); ++x) {
            const size_t k = static_cast<size_t>(y) * a.w + x;
            if (both[k]) {
              s += diff[k];
              ++m;
            }
          }
        if (m > 0) tiles.push_back(s / m);
      }
    if (tiles.size() >= 2) {
      double mean = 0.0, ss = 0.0;
      for (double t : tiles) mean += t;
      mean /= static_cast<double>(tiles.size());
      for (double t : tiles) ss += (t - mean) * (t - mean);
      const double sd = std::sqrt(ss / static_cast<double>(tiles.size() - 1));
      c.sigma_mean = sd / std::sqrt(static_cast<double>(tiles.size()));
    } else {
      c.sigma_mean = std::numeric_limits<double>::infinity();  // one tile: cannot tell
    }
  }
  if (c.noise_rule == "deterministic") c.pixel_threshold = kRoundOff;
  size_t changed = 0;
  for (size_t k = 0; k < n; ++k) changed += both[k] && std::abs(diff[k]) > threshold[k];
  c.changed_pixels = static_cast<double>(changed) / count;
  return c;
}

double change_threshold(const ImageChange& c, double change_mean_shift) {
  return std::max(change_mean_shift, kSigmas * c.sigma_mean);
}

std::string change_phrase(const ImageChange& c) {
  char text[120];
  std::snprintf(text, sizeof text, "%s by %.3f mean AO on %.0f %% of pixels",
                c.mean_shift < 0.0 ? "darker" : "brighter", std::abs(c.mean_shift),
                100.0 * c.changed_pixels);
  return text;
}

}  // namespace aoeval
