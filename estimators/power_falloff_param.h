// The falloff parameters of a ray-cast estimator (CONTRACT §3), declared once: `falloff`, a choice
// of none, linear, sqrt, exp or power, and `falloff_k`, the exponent K of power:K (rho(x) = x^K, 1
// = linear, 0.5 = sqrt). raytraced and rtao declare their falloff with falloff_params() and read it
// with falloff_of(); obscurances, whose rho list differs, declares only the exponent
// (power_exponent_param): one default and one range for all of them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

inline ParamSpec power_exponent_param(std::string name, std::string meaning) {
  return real_param({.name = std::move(name),
                     .def = 2.0,
                     .min = 1e-3,
                     .max = 1e3,
                     .spacing = Spacing::linear,
                     .unit = "",
                     .meaning = std::move(meaning)});
}

// `falloff` and `falloff_k`, in this order; `range` names the estimator's own range parameter
// (raytraced's dmax, rtao's t_max) in the meanings.
inline std::vector<ParamSpec> falloff_params(const std::string& range) {
  return {
      choice_param(
          {.name = "falloff",
           .def = "none",
           .choices = {"none", "linear", "sqrt", "exp", "power"},
           .meaning = "occluder weight 1 - rho(d/" + range +
                      "): none, linear, sqrt, exp or power (rho(x) = x^falloff_k) (CONTRACT §3)"}),
      power_exponent_param("falloff_k",
                           "the exponent K of falloff power, rho(x) = x^K (1 = linear, 0.5 = "
                           "sqrt); unused otherwise")};
}

// The falloff that falloff_params() select: power:falloff_k for power, else the named one.
inline Falloff falloff_of(const ParamSet& p) {
  const std::string falloff = p.choice("falloff");
  const double k = p.real("falloff_k");  // read always: every declared parameter is read
  return falloff == "power" ? Falloff::power(k) : parse_falloff(falloff, "falloff");
}

}  // namespace aoeval
