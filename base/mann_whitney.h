// The rank test of timings (CONTRACT §12's "slower" and the timing figures): Mann-Whitney U, exact
// or by the normal approximation. On the ground floor because the dashboard (reports/) and the
// figures (harness/figures/) both judge times with it, and neither may borrow from the other.
#pragma once

#include <vector>

namespace aoeval {

// Mann-Whitney U (Wilcoxon rank-sum) test of `after` against `before`. u is the U statistic of
// `after`: the number of pairs (before_i, after_j) with after_j > before_i, ties counting 1/2
// (u = R_after - n_after (n_after + 1) / 2 with mid-ranks). p_greater = P(U >= u) under H0
// (after is stochastically larger: "slower" for times), p_less = P(U <= u), p_two_sided =
// min(1, 2 min(p_greater, p_less)). Exact (the
// permutation distribution of the mid-rank sum, counted by dynamic programming, so ties are exact
// too) when n_before + n_after <= exact_limit; otherwise the normal approximation with
// tie-corrected variance and continuity correction. Needs at least one sample on each side
// (std::invalid_argument otherwise).
struct RankTest {
  double u = 0.0;
  double p_greater = 1.0, p_less = 1.0, p_two_sided = 1.0;
  bool exact = false;
};
RankTest mann_whitney(const std::vector<double>& before, const std::vector<double>& after,
                      int exact_limit = 60);

// The smallest one-sided p-value the exact test can give for sample sizes m and n: 1 / C(m+n, m).
// Below time_alpha no rank test can say "slower", whatever the times (reported, never silent).
double smallest_one_sided_p(int m, int n);

}  // namespace aoeval
