// Welch's t-test on the logarithms of timings: the dashboard's time test where the rank test
// cannot reach its alpha (base/mann_whitney.h smallest_one_sided_p, 1 / C(m + n, m), not below
// alpha: at alpha 0.01, 3 against up to 6 repetitions or 4 against 4; 4 against 5 can). A suite
// that times a point until its spread is small (harness/evaluation/ repetition_policy.h: 3
// repetitions when all three lie within +-5 % of their median) leaves 3 samples, where no
// permutation test gets below 1/20 one-sided. On logs, a time's noise is multiplicative (a slower
// machine state scales every pass), and the statistic compares the mean log times, i.e. the
// geometric means: t = (mean log after - mean log before) / sqrt(s_a^2 / n_a + s_b^2 / n_b), with
// the Welch-Satterthwaite degrees of freedom (Welch 1947), p from Student's t (Boost.Math).
// Parametric: it assumes log-normal noise, which 3 samples within +-5 % cannot refute; it is used
// only where the rank test cannot decide, and the dashboard says which test judged.
#pragma once

#include <vector>

namespace aoeval {

struct LogTTest {
  double t = 0.0;                        // > 0: after slower
  double df = 0.0;                       // Welch-Satterthwaite degrees of freedom
  double p_greater = 1.0, p_less = 1.0;  // one-sided: after slower, after faster
};

// Needs at least 2 positive samples a side (std::invalid_argument otherwise). Two sides with no
// spread at all: p 0 on the side their means differ to, 1 on the other (and 1, 1 when equal),
// df infinite.
LogTTest welch_log_t_test(const std::vector<double>& before, const std::vector<double>& after);

}  // namespace aoeval
