// Test suites parameterised over the registry (conformance, default agreement): one test per
// registered estimator, named after it, so a new estimator is covered without a line of test code.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <vector>

#include "estimators/registry.h"

namespace aoeval::testing_support {

inline std::vector<std::string> registered_estimator_names() {
  std::vector<std::string> names;
  for (const auto& e : estimator_registry()) names.push_back(e.name);
  return names;
}

// "hbao-split-cpu" -> "hbao_split_cpu": GoogleTest names allow only letters, digits and '_'.
inline std::string estimator_test_name(const ::testing::TestParamInfo<std::string>& p) {
  std::string s = p.param;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

}  // namespace aoeval::testing_support

// Instantiates SUITE once per registered estimator.
#define AOEVAL_INSTANTIATE_OVER_REGISTRY(SUITE)                                     \
  INSTANTIATE_TEST_SUITE_P(                                                         \
      Registry, SUITE,                                                              \
      ::testing::ValuesIn(::aoeval::testing_support::registered_estimator_names()), \
      ::aoeval::testing_support::estimator_test_name)
