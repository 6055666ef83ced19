// What the figures' check tests share: every check of a list passing (or failing), and synthetic
// timing repetitions for the rank-test checks.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "harness/figures/figure.h"

namespace aoeval::figures::testing {

inline void expect_all(const std::vector<Check>& checks, bool passed, const char* what) {
  ASSERT_FALSE(checks.empty()) << what;
  for (const Check& c : checks)
    EXPECT_EQ(c.passed, passed) << what << ": " << c.rule << " -> " << c.measured;
}

// n repetitions around `ms` with a small deterministic spread (+-1 %).
inline std::vector<double> times(double ms, int n = 9) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(ms * (1.0 + 0.01 * ((i * 7) % 5 - 2) / 2.0));
  return v;
}

}  // namespace aoeval::figures::testing
