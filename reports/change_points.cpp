// E-Divisive means with a tolerance or a permutation test (see change_points.h).
#include "reports/change_points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>

namespace aoeval {

namespace {

struct Split {
  size_t k = 0;  // relative to the segment
  double q = -1.0;
};

// The split of `v` with the largest Q (change_points.h), both parts at least `min_seg` long.
// O(n^2) through a 2-D prefix sum of the distance matrix.
Split best_split(const std::vector<double>& v, size_t min_seg) {
  const size_t n = v.size();
  std::vector<double> prefix((n + 1) * (n + 1), 0.0);  // prefix[i][j] = sum_{a<i, b<j} |v_a - v_b|
  auto at = [&](size_t i, size_t j) -> double& { return prefix[i * (n + 1) + j]; };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      at(i + 1, j + 1) = std::abs(v[i] - v[j]) + at(i, j + 1) + at(i + 1, j) - at(i, j);
  auto block = [&](size_t a0, size_t a1, size_t b0, size_t b1) {
    return at(a1, b1) - at(a0, b1) - at(a1, b0) + at(a0, b0);
  };
  Split best;
  for (size_t k = min_seg; k + min_seg <= n; ++k) {
    const double m = static_cast<double>(k), r = static_cast<double>(n - k);
    const double cross = block(0, k, k, n);
    const double left = m > 1 ? block(0, k, 0, k) / 2.0 / (m * (m - 1) / 2.0) : 0.0;
    const double right = r > 1 ? block(k, n, k, n) / 2.0 / (r * (r - 1) / 2.0) : 0.0;
    const double q = m * r / (m + r) * (2.0 * cross / (m * r) - left - right);
    if (q > best.q) best = {k, q};
  }
  return best;
}

double mean_of(const std::vector<double>& v, size_t a, size_t b) {
  double s = 0.0;
  for (size_t i = a; i < b; ++i) s += v[i];
  return s / static_cast<double>(b - a);
}

double median_of(const std::vector<double>& v, size_t a, size_t b) {
  std::vector<double> part(v.begin() + static_cast<long>(a), v.begin() + static_cast<long>(b));
  std::sort(part.begin(), part.end());
  const size_t n = part.size();
  return n % 2 ? part[n / 2] : 0.5 * (part[n / 2 - 1] + part[n / 2]);
}

// Tolerance test of the split at k of segment [lo, hi) of `x`. No scatter term: a segment found
// first may span several levels, whose spread is no noise (quality noise is in the tolerance).
bool tolerance_accepts(const std::vector<double>& x, size_t lo, size_t k, size_t hi,
                       const ChangePointOptions& o, ChangePoint& cp) {
  const double ml = mean_of(x, lo, k), mr = mean_of(x, k, hi);
  cp = {k, ml, mr, 0.0};
  return std::abs(mr - ml) > std::max(o.relative * std::abs(ml), o.absolute);
}

// Permutation test of the split at k of segment [lo, hi) of the log values `y`.
bool permutation_accepts(const std::vector<double>& y, size_t lo, size_t k, size_t hi, double q,
                         const ChangePointOptions& o, ChangePoint& cp) {
  std::vector<double> seg(y.begin() + static_cast<long>(lo), y.begin() + static_cast<long>(hi));
  std::mt19937_64 rng(0x5eedc0deULL + lo * 1315423911ULL + hi);  // fixed: same history, same p
  int as_large = 0;
  for (int r = 0; r < o.permutations; ++r) {
    for (size_t i = seg.size() - 1; i > 0; --i) std::swap(seg[i], seg[rng() % (i + 1)]);
    if (best_split(seg, 2).q >= q) ++as_large;
  }
  const double p = (1.0 + as_large) / (1.0 + o.permutations);
  const double before = std::exp(median_of(y, lo, k)), after = std::exp(median_of(y, k, hi));
  cp = {k, before, after, p};
  const double ratio = std::max(after / before, before / after);
  return p <= o.alpha && ratio > 1.0 + o.relative;
}

}  // namespace

std::vector<ChangePoint> change_points(const std::vector<double>& series,
                                       const ChangePointOptions& o) {
  const bool permute = o.test == ChangePointOptions::Test::permutation;
  std::vector<double> x = series;
  for (double& v : x) {
    if (!std::isfinite(v) || (permute && v <= 0.0))
      throw std::invalid_argument("change_points: a value is not finite (or, for times, not > 0)");
    if (permute) v = std::log(v);
  }
  const size_t min_seg = permute ? 2 : 1;
  std::vector<ChangePoint> found;
  std::vector<std::pair<size_t, size_t>> todo = {{0, x.size()}};
  while (!todo.empty()) {
    const auto [lo, hi] = todo.back();
    todo.pop_back();
    if (hi - lo < 2 * min_seg) continue;
    const std::vector<double> seg(x.begin() + static_cast<long>(lo),
                                  x.begin() + static_cast<long>(hi));
    const Split s = best_split(seg, min_seg);
    if (s.q <= 0.0) continue;  // a flat segment
    const size_t k = lo + s.k;
    ChangePoint cp;
    const bool accepted = permute ? permutation_accepts(x, lo, k, hi, s.q, o, cp)
                                  : tolerance_accepts(x, lo, k, hi, o, cp);
    if (!accepted) continue;
    found.push_back(cp);
    todo.emplace_back(lo, k);
    todo.emplace_back(k, hi);
  }
  std::sort(found.begin(), found.end(),
            [](const ChangePoint& a, const ChangePoint& b) { return a.index < b.index; });
  // Each step's levels are those of its neighbouring final segments, not of the larger segment
  // it was found in (two steps in a row each report their own before and after).
  auto level = [&](size_t a, size_t b) {
    return permute ? std::exp(median_of(x, a, b)) : mean_of(x, a, b);
  };
  for (size_t i = 0; i < found.size(); ++i) {
    const size_t a = i == 0 ? 0 : found[i - 1].index;
    const size_t b = i + 1 == found.size() ? x.size() : found[i + 1].index;
    found[i].before = level(a, found[i].index);
    found[i].after = level(found[i].index, b);
  }
  return found;
}

}  // namespace aoeval
