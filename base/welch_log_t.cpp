#include "base/welch_log_t.h"

#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

namespace aoeval {

namespace {

struct LogMoments {
  double mean = 0.0, variance = 0.0;  // sample variance (n - 1)
  double n = 0.0;
};

LogMoments log_moments(const std::vector<double>& x, const char* side) {
  if (x.size() < 2)
    throw std::invalid_argument(std::string("welch_log_t_test: fewer than 2 samples ") + side);
  LogMoments m;
  m.n = static_cast<double>(x.size());
  for (double v : x) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("welch_log_t_test: a time that is not positive ") +
                                  side);
    m.mean += std::log(v);
  }
  m.mean /= m.n;
  for (double v : x) m.variance += (std::log(v) - m.mean) * (std::log(v) - m.mean);
  m.variance /= m.n - 1.0;
  return m;
}

}  // namespace

LogTTest welch_log_t_test(const std::vector<double>& before, const std::vector<double>& after) {
  const LogMoments b = log_moments(before, "before"), a = log_moments(after, "after");
  const double vb = b.variance / b.n, va = a.variance / a.n;
  const double se2 = vb + va;
  LogTTest r;
  const double difference = a.mean - b.mean;
  // Both sides without spread (up to the rounding of a mean of equal logs): the difference is
  // known exactly, and one of rounding size is none.
  if (!(se2 > 1e-24)) {
    const double known = std::abs(difference) > 1e-12 ? difference : 0.0;
    r.p_greater = known > 0.0 ? 0.0 : 1.0;
    r.p_less = known < 0.0 ? 0.0 : 1.0;
    r.t = known > 0.0 ? INFINITY : known < 0.0 ? -INFINITY : 0.0;
    r.df = INFINITY;
    return r;
  }
  r.t = difference / std::sqrt(se2);
  r.df = se2 * se2 / (vb * vb / (b.n - 1.0) + va * va / (a.n - 1.0));
  const boost::math::students_t dist(r.df);
  r.p_greater = boost::math::cdf(boost::math::complement(dist, r.t));
  r.p_less = boost::math::cdf(dist, r.t);
  return r;
}

}  // namespace aoeval
