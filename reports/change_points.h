// Where did a series step? (CONTRACT §12 `aoeval dashboard --history N`.) One value per run, oldest
// first; the answer is the runs where the series moved to a new level.
//
// Method: E-Divisive means (Matteson & James 2014, "A Nonparametric Approach for Multiple Change
// Point Analysis of Multivariate Data", JASA 109(505): eq. 3-5 with alpha = 1), as Apache Otava
// and MongoDB's Hunter (Fleming et al. 2023, "Hunter: Using Change Point Detection to Hunt for
// Performance Regressions", ICPE) use it: binary segmentation. In a segment, the split k where
//   Q(k) = m n / (m + n) * [ 2/(m n) sum |x_i - y_j| - 1/C(m,2) sum |x_i - x_i'| - 1/C(n,2) sum
//          |y_j - y_j'| ]     (x: the m values before k, y: the n from k on)
// peaks is the candidate; it is kept when the series' test accepts it, and both halves are
// searched again; the search stops in a segment whose best candidate is refused. One run away
// inside a level (up, then back) is an outlier, not a level: every split around it has Q = 0. At
// the ends of the history a one-run level is a step (quality) or waits for a second run (times).
// Chosen over Perfherder's windowed t-tests because it needs no window (a dashboard may hold only 8
// runs) and finds several steps at once, and over asv's L1 step fit because its permutation test
// gives a false-alarm rate that holds for any noise distribution, which timing noise needs.
//
// Two tests, by the kind of series:
//   tolerance   quality series (rmse_excess, mean AO): nearly deterministic (the same point on the
//               same reference repeats bit for bit), so a step is a level change larger than a
//               tolerance, max(relative * |level before|, absolute) (the caller puts the
//               series' own noise, e.g. the reference's, into `absolute`). Segments may be one run
//               long.
//   permutation times: Matteson & James's permutation test of the segment's largest Q on the log
//               values (multiplicative noise): p = (1 + #{permutations whose largest Q >= the
//               observed}) / (1 + permutations), from a fixed-seed generator (same history, same
//               answer); kept when p <= alpha AND the segments' medians differ by more than the
//               factor 1 + relative (the dashboard's time_relative: a statistically sure but small
//               drift of a shared machine is no step). Segments are at least two runs long, so one
//               slow run is never a step by itself (a new level is named once a second run
//               confirms it; the two-run dashboard already judges the newest run).
// False-alarm rates measured on pure noise are in change_points_test.cpp and the README.
#pragma once

#include <cstddef>
#include <vector>

namespace aoeval {

struct ChangePointOptions {
  enum class Test { tolerance, permutation };
  Test test = Test::tolerance;
  double relative = 0.0;  // tolerance: fraction of |level before|; permutation: median ratio - 1
  double absolute = 0.0;  // tolerance only
  double alpha = 0.01;    // permutation only
  int permutations = 199;
};

struct ChangePoint {
  size_t index = 0;                  // the first value of the new level
  double before = 0.0, after = 0.0;  // the two segments' levels (means; medians for times)
  double p = 0.0;                    // permutation p-value (0 for the tolerance test)
};

// The steps of `series`, in order of index. Non-finite values are an std::invalid_argument.
std::vector<ChangePoint> change_points(const std::vector<double>& series,
                                       const ChangePointOptions& options);

}  // namespace aoeval
