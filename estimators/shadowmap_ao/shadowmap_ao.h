// shadowmap-ao: Matt Pharr and Simon Green, 2004, "Ambient Occlusion", GPU Gems, chapter 17,
// §17.3 "Hardware-Accelerated Occlusion": "surround the object with a large spherical array of
// shadow-mapped lights. The occlusion amount at a point on a surface is simply the average of the
// shadow contributions from each light." Here on Vulkan (lavapipe by default):
//
// - n directional lights (§17.3: "128 to 1024 is required for good results") on the sphere, or on
//   the upper (+Y) dome over a ground plane ("a dome or a hemisphere can be used instead"), placed
//   either uniformly (the chapter's recommendation: a spherical Fibonacci lattice under a seeded
//   random rotation) or at evenly spaced latitudes and longitudes (which "tends to concentrate too
//   many samples at the poles"; the poles are ±Y).
// - Per light, a depth-only orthographic shadow map (shadowmap_depth.vert/.frag) whose depth range
//   covers the scene's bounding sphere and whose lateral extent, with fit = receivers (default),
//   is the receivers' extent as that light sees them (the camera's visible points, or the baked
//   vertices' triangle centres), as cascaded shadow maps are fitted to the view: the texels go
//   where they are read, so a small occluder over a large ground keeps its size in texels. fit =
//   scene is the chapter's whole-scene map (the bounding sphere laterally too). `lights_per_pass`
//   maps share one atlas and are tested together in one accumulation pass (§17.3: "accumulate eight
//   shadows in the shader at once ... only n + n/8 renders"), shadowmap_accumulate.comp.
// - Each receiver adds, per light above its surface, weight w (1, or n·l for cosine weighting) to
//   its total and w·lit to its lit sum; lights below the surface are the chapter's "side of the
//   surface facing away from the light is always black". AO = lit sum / total: a ratio
//   estimator, exactly 1 on an open surface. In dome mode the lights' mirror images below the
//   horizon enter the total only (the ground plane the dome assumes blocks them), so a surface that
//   faces sideways is still normalised over its whole hemisphere. The mean lit direction
//   (unweighted, the chapter's "direction to the light multiplied by the shadow value", normalised)
//   is written as bent.X/Y/Z.
// - Receivers: mode=pixel, every covered pixel of the camera's G-buffer (its P, N and Ng, uploaded
//   to the device); mode=vertex, the chapter's use of the values as a bake: the centre of every
//   triangle, both sides, area-averaged to the vertices and interpolated per pixel exactly as
//   vertex-baked (§17.2, §17.4) does, so the two compare at equal light/ray counts.
// - Depth bias at the receiver, in shadow-map texels: bias + slope_bias · tan(θ), θ the angle
//   between the light and the geometric normal (tan capped at kMaxBiasTan, see there).
//
// AO definition: the `weighting` parameter's (uniform = the chapter's accessibility, cosine),
// unbounded. Passes timed with GPU timestamps: shadow_maps_ms and accumulate_ms.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

enum class LightDistribution { uniform, latlong };
enum class ShadowmapMode { pixel, vertex };

// Filled from the ParamSet; the defaults live in the declaration's table only.
struct ShadowmapSettings {
  int lights = 0;
  int resolution = 0;  // texels per side of each shadow map
  LightDistribution distribution = LightDistribution::uniform;
  bool dome = false;
  float bias = 0.0f, slope_bias = 0.0f;  // texels
  int lights_per_pass = 0;
  Weighting weighting = Weighting::uniform;
  ShadowmapMode mode = ShadowmapMode::pixel;
  bool fit_receivers = true;  // false: every map spans the scene's bounding sphere
  uint64_t seed = 0;
};

// tan(θ) of the slope bias is capped here only to keep it finite. Within a texel a plane's map
// depth moves by up to 0.71 texel · tan θ from the texel centre's (half the diagonal), so a slope
// bias of 1 never self-shadows a plane as long as tan θ stays below the cap: a cap of 10 (tried)
// self-shadowed every light with cos θ < 0.1, 3 % of an open plane's lights. What the bias costs
// instead: a light at grazing angle misses occluders within (bias + slope_bias · tan θ) texels
// along its direction (light leaks near contacts; the closed-box test runs without bias).
inline constexpr float kMaxBiasTan = 1000.0f;

// The lights' unit directions (towards the light), deterministic from the seed.
std::vector<glm::vec3> light_directions(int count, LightDistribution distribution, bool dome,
                                        uint64_t seed);

ShadowmapSettings shadowmap_settings(const ParamSet& p);

EstimatorInfo shadowmap_ao_estimator();

}  // namespace aoeval
