// The `seed` parameter of a stochastic estimator, declared once: default 7 and range 0..1e15 for
// every built-in (the references use seed 1, so an estimator at its default never shares their
// samples; frame k of a sequence runs with seed + k, CONTRACT §10). Each estimator says what the
// seed draws.
#pragma once

#include <string>
#include <utility>

#include "estimators/estimator.h"

namespace aoeval {

inline ParamSpec seed_param(std::string meaning) {
  return int_param({.name = "seed",
                    .def = 7,
                    .min = 0,
                    .max = 1e15,
                    .spacing = Spacing::linear,
                    .unit = "",
                    .meaning = std::move(meaning)});
}

}  // namespace aoeval
