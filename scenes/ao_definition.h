// What an AO value means (CONTRACT §3): the weighting of directions, the range dmax and the falloff
// of an occluder's weight with distance. The reference computes a definition; every estimator
// declares the one it estimates; the harness scores each estimator against the reference of its own
// definition ("matched") and against unbounded cosine AO ("true AO").
#pragma once

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

namespace aoeval {

enum class Weighting {
  cosine,   // (1/pi) Int V(w) cos(theta) dw: Dimitrov et al. 2008 eq. 1, Mendez et al. obscurances
  uniform,  // (1/2pi) Int V(w) dw: Hegeman et al. 2006 eq. 3, GPU Gems ch. 17 "accessibility"
};

// The obscurance function rho of an occluder's distance x = d / dmax (CONTRACT §3). A kind, and
// for `power` the exponent K. Built only from the constants below and power(K), which
// canonicalises power:1 to linear and power:0.5 to sqrt: one definition has one name, one label
// and one reference cache key, so a plug-in declaring power:1 is scored against the very
// reference (cached or not) that a linear one is.
struct Falloff {
  enum class Kind {
    none,    // an occluder closer than dmax counts fully, beyond it not at all
    linear,  // rho(x) = x: the linear attenuation of Dimitrov et al. 2008 §3.5, W(r) = 1 - r/R
    sqrt,    // rho(x) = sqrt(x): the square-root obscurance function of Mendez et al. 2003 §3
    exp,     // rho(x) = (1 - e^(-4x)) / (1 - e^(-4)): Mendez et al.'s exponential shape,
             // normalised so that rho(1) = 1 (continuous at dmax)
    power,   // rho(x) = x^K, K > 0 (K = 1, 0.5 are stored as linear, sqrt)
  };
  Kind kind = Kind::none;
  double k = 1.0;  // the exponent K of `power`; 1 for every other kind

  static const Falloff none, linear, sqrt, exp;
  // power:K; InputError unless K is a positive finite number.
  static Falloff power(double k);
  bool operator==(const Falloff&) const = default;
};
inline constexpr Falloff Falloff::none{Falloff::Kind::none, 1.0};
inline constexpr Falloff Falloff::linear{Falloff::Kind::linear, 1.0};
inline constexpr Falloff Falloff::sqrt{Falloff::Kind::sqrt, 1.0};
inline constexpr Falloff Falloff::exp{Falloff::Kind::exp, 1.0};

struct AoDefinition {
  Weighting weighting = Weighting::cosine;
  double dmax = std::numeric_limits<double>::infinity();  // scene units
  Falloff falloff = Falloff::none;

  bool bounded() const { return std::isfinite(dmax); }

  // The accessibility one ray contributes when its first hit is at distance d (infinity = no hit):
  // 1 - occluder weight, where the weight is 1 - rho(d / dmax) for d < dmax and 0 beyond. With
  // falloff none that is 0 for d < dmax and 1 otherwise.
  float ray_value(float d) const {
    if (!(d < dmax)) return 1.0f;
    const float x = static_cast<float>(d / dmax);
    switch (falloff.kind) {
      case Falloff::Kind::none:
        return 0.0f;
      case Falloff::Kind::linear:
        return x;
      case Falloff::Kind::sqrt:
        return std::sqrt(x);
      case Falloff::Kind::exp:
        return (1.0f - std::exp(-4.0f * x)) / (1.0f - std::exp(-4.0f));
      case Falloff::Kind::power:
        return std::pow(x, static_cast<float>(falloff.k));
    }
    return 0.0f;
  }

  // {"weighting": "cosine", "dmax": null (unbounded) or a number, "falloff": "none"}
  nlohmann::json to_json() const;
  // Short stable text for run names and cache keys, e.g. "cosine", "uniform/dmax:0.5/linear".
  std::string label() const;
  bool operator==(const AoDefinition&) const = default;
};

const char* weighting_name(Weighting w);
// "none", "linear", "sqrt", "exp" or "power:K" with K in its shortest round-trip form ("power:3").
std::string falloff_name(Falloff f);
// Parse the command-line words; InputError naming `option` and the choices otherwise. A falloff
// is one of the names above; "power:K" needs K a positive finite number (power:1 -> linear,
// power:0.5 -> sqrt).
Weighting parse_weighting(const std::string& text, const std::string& option = "--weighting");
Falloff parse_falloff(const std::string& text, const std::string& option = "--falloff");
// "inf", "none" or "" -> unbounded; otherwise a positive finite number.
double parse_dmax(const std::string& text, const std::string& option = "--dmax");
// Checks the combination (a falloff needs a finite dmax); InputError naming the options.
void validate_definition(const AoDefinition& d);

// Unbounded cosine-weighted AO: what "true AO" means in every results row.
inline AoDefinition true_ao_definition() {
  return AoDefinition{};
}

}  // namespace aoeval
