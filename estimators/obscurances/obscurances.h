// obscurances: Méndez, Sbert, Catà, "Ray-traced obscurances" (2003), the view-dependent obscurances
// of a pixel's surface point P, estimated by Monte Carlo with Embree rays (their §4.1, "obscurance
// rays", and §4.2 systematic sampling). The seed's text extract lost the displayed formulas; they
// are reconstructed here from the prose (and named by their equation numbers):
//
//   eq. 2   W(P) = (1/pi) Int_Omega rho(d(P, w)) cos(theta) dw, with rho(d) = 1 for d >= dmax
//           ("obscurance", 1 = open); d(P, w) = distance to the first hit along w (inf = none).
//   eq. 3   R_ave = (1/A_T) Sum_i A_i R_i: the area-weighted average reflectivity of the scene.
//   eq. 4-5 colour bleeding (their §2.3): the R_ave factor of the ambient term moves into the
//           integral as the reflectivity of the point Q that P sees along w:
//             W_rgb(P) = (1/pi) Int_Omega R(Q) rho(d(P, w)) cos(theta) dw,
//           and where nothing is hit closer than dmax, R(Q) = R_ave (eq. 6, the "no hit" rule).
//           So a ray that hits Q at d < dmax is worth R(Q) rho(d / dmax), one that does not is
//           worth R_ave; with rho = constant (rho = 0 inside dmax) the hits are black, hence
//           "the constant function ... does not present color bleeding" (§3, Fig. 4 row 3).
//   §3      rho families, normalised to d / dmax (the falloffs of CONTRACT §3, AoDefinition):
//           sqrt: rho(x) = sqrt(x); exp: rho(x) = (1 - e^(-4x)) / (1 - e^(-4));
//           constant: rho(x) = 0 for x < 1, i.e. ambient occlusion with range dmax (Fig. 4 (3)).
//           power (not Mendez et al.'s; CONTRACT §3 power:K): rho(x) = x^K with K = rho_k.
//
// Estimator: Nobs = `rays` directions per pixel drawn with pdf cos(theta)/pi around the shading
// normal, so W = mean of the ray values (the cos/pi cancels). Sampling: i.i.d. (`random`) or the
// systematic sampling of §4.2 (one random offset shared by an n1 x n2 grid, n1 n2 = Nobs, mapped
// through the concentric cosine map: sampling/samplers.h, SamplerKind::stratified). A direction
// below the geometric surface counts as a hit at distance 0 (grey value rho(0) = 0, colour 0), as
// the reference does. With the random sampler and the same seed the grey output equals the Embree
// reference (sampling/ao_tracer.h) with spp = rays bit for bit: same directions, origins, values.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "estimators/estimator.h"
#include "sampling/samplers.h"

namespace aoeval {

struct ObscuranceSettings {
  // No defaults here: the parameter table declares them once; obscurance_settings_of fills this
  // from a ParamSet (default_params(...) for "every parameter at its default").
  int rays;              // Nobs, §4.1 (Fig. 6 uses 16)
  double dmax;           // scene units, eq. 2 (Fig. 4: 1.0 m)
  Falloff rho;           // §3; none = the constant function, power = x^rho_k
  SamplerKind sampling;  // stratified = systematic, §4.2
  uint64_t seed;
};

struct ObscuranceImage {
  std::vector<float> grey;               // W(P), eq. 2: the AO output; 0 where not covered
  std::vector<glm::vec3> rgb;            // W_rgb(P), eq. 5-6: the colour-bleeding obscurance
  glm::vec3 average_reflectivity{0.0f};  // R_ave, eq. 3
};

// eq. 3: the area-weighted mean of SceneObject::albedo over every triangle of the scene.
glm::vec3 average_reflectivity(const Scene& scene);

// One frame. Deterministic: the same settings give the same bits whatever the thread count.
ObscuranceImage compute_obscurances(const EmbreeScene& scene, const GBuffer& gbuffer,
                                    const ObscuranceSettings& settings, glm::vec3 r_ave);

// "exp" / "sqrt" / "constant" -> Falloff exp / sqrt / none; InputError naming `rho` otherwise.
Falloff parse_rho(const std::string& name);

EstimatorInfo obscurances_estimator();
ObscuranceSettings obscurance_settings_of(const ParamSet& params);

}  // namespace aoeval
