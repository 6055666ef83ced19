#include "base/mann_whitney.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aoeval {

namespace {

// Mid-ranks (1-based) of the pooled sample, doubled so that they are integers.
std::vector<long> doubled_midranks(const std::vector<double>& pooled) {
  const size_t n = pooled.size();
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return pooled[a] < pooled[b]; });
  std::vector<long> rank2(n);
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j + 1 < n && pooled[order[j + 1]] == pooled[order[i]]) ++j;
    const long r2 = static_cast<long>(i + 1 + j + 1);  // 2 * mean of ranks i+1 .. j+1
    for (size_t k = i; k <= j; ++k) rank2[order[k]] = r2;
    i = j + 1;
  }
  return rank2;
}

// Exact permutation distribution of the doubled rank sum of `n` items drawn from `rank2`:
// ways[s] = number of n-subsets with doubled rank sum s (the conditional distribution given the
// ties, so ties need no approximation).
std::vector<double> rank_sum_counts(const std::vector<long>& rank2, int n) {
  long max_sum = 0;
  for (long r : rank2) max_sum += r;
  std::vector<std::vector<double>> ways(n + 1, std::vector<double>(max_sum + 1, 0.0));
  ways[0][0] = 1.0;
  int seen = 0;
  for (long r : rank2) {
    ++seen;
    for (int c = std::min(seen, n); c >= 1; --c)
      for (long s = max_sum; s >= r; --s) ways[c][s] += ways[c - 1][s - r];
  }
  return ways[n];
}

double normal_upper(double z) {
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace

RankTest mann_whitney(const std::vector<double>& before, const std::vector<double>& after,
                      int exact_limit) {
  const int m = static_cast<int>(before.size()), n = static_cast<int>(after.size());
  if (m == 0 || n == 0) throw std::invalid_argument("mann_whitney: a sample is empty");
  std::vector<double> pooled = before;
  pooled.insert(pooled.end(), after.begin(), after.end());
  const std::vector<long> rank2 = doubled_midranks(pooled);
  long after_sum2 = 0;
  for (int j = 0; j < n; ++j) after_sum2 += rank2[m + j];
  RankTest t;
  t.u = 0.5 * static_cast<double>(after_sum2) - 0.5 * n * (n + 1.0);
  const int total = m + n;
  if (total <= exact_limit) {
    const std::vector<double> ways = rank_sum_counts(rank2, n);
    double all = 0.0, ge = 0.0, le = 0.0;
    for (size_t s = 0; s < ways.size(); ++s) {
      all += ways[s];
      if (static_cast<long>(s) >= after_sum2) ge += ways[s];
      if (static_cast<long>(s) <= after_sum2) le += ways[s];
    }
    t.p_greater = ge / all;
    t.p_less = le / all;
    t.exact = true;
  } else {
    // Normal approximation: E U = mn/2, Var U = mn/12 ((N+1) - sum(t^3 - t) / (N (N-1))) over tie
    // groups of size t; continuity correction 1/2.
    std::vector<long> sorted = rank2;
    std::sort(sorted.begin(), sorted.end());
    double tie_term = 0.0;
    for (size_t i = 0; i < sorted.size();) {
      size_t j = i;
      while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
      const double g = static_cast<double>(j - i);
      tie_term += g * g * g - g;
      i = j;
    }
    const double mean = 0.5 * m * n;
    const double var = m * n / 12.0 * ((total + 1.0) - tie_term / (total * (total - 1.0)));
    if (var <= 0.0) {
      t.p_greater = t.p_less = 1.0;
    } else {
      const double sd = std::sqrt(var);
      t.p_greater = normal_upper((t.u - mean - 0.5) / sd);
      t.p_less = normal_upper((mean - t.u - 0.5) / sd);
    }
  }
  t.p_greater = std::min(1.0, t.p_greater);
  t.p_less = std::min(1.0, t.p_less);
  t.p_two_sided = std::min(1.0, 2.0 * std::min(t.p_greater, t.p_less));
  return t;
}

double smallest_one_sided_p(int m, int n) {
  double c = 1.0;  // C(m+n, m) built up as a product, exact in double for the sizes used here
  for (int k = 1; k <= m; ++k) c = c * (n + k) / k;
  return 1.0 / c;
}

}  // namespace aoeval
