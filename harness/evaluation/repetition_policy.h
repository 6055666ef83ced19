// How many timed repetitions a still point gets (issue 42, build 5): a fixed count (the sweep
// spec's "repetitions", CONTRACT §5), or, when the spec also gives "max_repetitions", as many as
// the timing's own spread asks: at least "repetitions", at most "max_repetitions", stopping once
// the median's confidence interval is within +-"median_ci" (default 0.05) of the median.
//
// The interval is distribution-free (order statistics: [x(j), x(n+1-j)] holds the true median
// with probability 1 - 2 P(Binomial(n, 1/2) < j)); j is the largest with that coverage >= 95 %,
// and below 6 samples, where no interval reaches 95 %, the range [min, max] (coverage 75 % at 3,
// 87.5 % at 4, 93.75 % at 5). So 3 repetitions stop early only when all three lie within +-5 %
// of their median; a noisy point keeps going until its 95 % interval is that narrow or the
// maximum is reached. The row's `repetitions` column says how many were used.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

struct TimingSpec;

struct MedianInterval {
  double lo = 0.0, hi = 0.0;  // ms
  double coverage = 0.0;      // the probability that [lo, hi] holds the true median
};
// The interval of `samples` described above; {0, 0, 0} when there are none.
MedianInterval median_interval(std::vector<double> samples);

// True when `times` (the repetitions timed so far) are enough under `timing`.
bool enough_repetitions(const TimingSpec& timing, const std::vector<double>& times);

// "1,5" (warm-up, repetitions), or "1,3-15@0.05" when adaptive: what tells two timings apart
// (suites run a point once per distinct reference and timing).
std::string timing_key(const TimingSpec& timing);

}  // namespace aoeval
