// The exponent K of the `power:K` falloff (CONTRACT §3: rho(x) = x^K, 1 = linear, 0.5 = sqrt),
// declared by every estimator whose falloff choice offers `power` (raytraced, obscurances): one
// default and one range for all of them.
#pragma once

#include <string>
#include <utility>

#include "estimators/estimator.h"

namespace aoeval {

inline ParamSpec power_exponent_param(std::string name, std::string meaning) {
  return {.name = std::move(name),
          .type = ParamType::real,
          .default_value = 2.0,
          .min = 1e-3,
          .max = 1e3,
          .log_scale = false,
          .unit = "",
          .meaning = std::move(meaning),
          .choices = {}};
}

}  // namespace aoeval
