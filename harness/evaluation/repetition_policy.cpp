#include "harness/evaluation/repetition_policy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "base/summary.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {

namespace {
// P(Binomial(n, 1/2) < j).
double binomial_below(int n, int j) {
  double sum = 0.0, term = std::pow(0.5, n);  // C(n, 0) / 2^n
  for (int i = 0; i < j; ++i) {
    sum += term;
    term = term * (n - i) / (i + 1);
  }
  return sum;
}
}  // namespace

MedianInterval median_interval(std::vector<double> samples) {
  const int n = static_cast<int>(samples.size());
  if (n == 0) return {};
  std::sort(samples.begin(), samples.end());
  int j = 1;  // 1-based order statistic: [x(j), x(n + 1 - j)]
  while (2 * (j + 1) <= n && 1.0 - 2.0 * binomial_below(n, j + 1) >= 0.95) ++j;
  return {samples[j - 1], samples[n - j], 1.0 - 2.0 * binomial_below(n, j)};
}

bool enough_repetitions(const TimingSpec& timing, const std::vector<double>& times) {
  const int n = static_cast<int>(times.size());
  const int least = std::max(1, timing.repetitions);
  if (n < least) return false;
  if (timing.max_repetitions <= least || n >= timing.max_repetitions) return true;
  const double mid = median(times);
  const MedianInterval ci = median_interval(times);
  return ci.hi - mid <= timing.median_ci * mid && mid - ci.lo <= timing.median_ci * mid;
}

std::string timing_key(const TimingSpec& timing) {
  char key[96];
  if (timing.max_repetitions > timing.repetitions)
    std::snprintf(key, sizeof key, "%d,%d-%d@%g", timing.warmup, timing.repetitions,
                  timing.max_repetitions, timing.median_ci);
  else
    std::snprintf(key, sizeof key, "%d,%d", timing.warmup, timing.repetitions);
  return key;
}

}  // namespace aoeval
