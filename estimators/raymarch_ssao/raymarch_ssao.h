// raymarch-ssao: Monte-Carlo ray marching in the depth buffer, the baseline that Dimitrov, Bavoil,
// Sainz 2008 ("Horizon-Split Ambient Occlusion") compare horizon-split AO against (§5, Fig. 12):
// `rays` cosine-distributed directions per pixel (pdf cos/pi, so eq. 1 becomes the mean of the
// ray values), each marched in Ns steps of R / Ns through the nearest-texel depth buffer (§4.1.1)
// exactly as hbao-split marches its normal rays (hbao_kernel.glsl, hbao_march: the same ISBELOW /
// INTERSECT test of Fig. 4, the same eq. 13 offset, a step jitter beta in (-1, 1) per ray, §4.1.2).
// A ray whose first occluder within R lies at distance r is worth 1 - W(r), W = 1 - r/R with
// attenuation (§3.5), W = 1 without; an escaping ray is worth 1. Declared AO definition: cosine,
// dmax = R, linear falloff with attenuation (none without), the same as hbao-split's.
#pragma once

#include <cstdint>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

struct RaymarchSettings {
  // No defaults here: the parameter table declares them once; raymarch_settings_of fills this from
  // a ParamSet (default_params(...) for "every parameter at its default").
  double radius;  // R
  int steps;      // Ns
  int rays;       // marches per pixel
  bool attenuation;
  bool offset;
  uint64_t seed;
};

// Deterministic: the same settings give the same bits whatever the thread count.
std::vector<float> raymarch_ssao(const GBuffer& gbuffer, const RaymarchSettings& settings);

EstimatorInfo raymarch_ssao_estimator();
RaymarchSettings raymarch_settings_of(const ParamSet& params);

}  // namespace aoeval
