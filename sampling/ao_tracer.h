// Monte-Carlo ambient occlusion with Embree at the shared G-buffer's surface points, with its own
// per-pixel standard error. The ground truth (references/, as many rays as it takes) and the
// raytraced estimator (estimators/raytraced/, a chosen cost) both trace with it, so neither depends
// on the other.
//
// Estimator (CONTRACT §3): AO(P) = E[value(w)] with w drawn with pdf cos(theta)/pi (cosine
// weighting) or 1/(2 pi) (uniform weighting) around the normal, and value(w) = 1 - the weight of
// the first occluder along w (AoDefinition::ray_value). Directions below the geometric surface (w .
// Ng <= 0) are occluded at distance 0. The bent normal is the value-weighted mean direction (GPU
// Gems ch. 17, "bent normals").
#pragma once

#include <cstdint>
#include <vector>

#include "base/coverage.h"
#include "sampling/ray_offset.h"
#include "sampling/samplers.h"
#include "scenes/ao_definition.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {

enum class NormalMode { shading, geometric };

// What to trace and, declared once here, the reference's defaults (CONTRACT §3): `aoeval
// reference`, sweep specs' "reference" block (harness ReferenceSpec), figures and benches all start
// from these (references/reference.h names them ReferenceSettings); the raytraced estimator sets
// every field from its own parameter table.
struct AoTraceSettings {
  int spp = 256;  // rays per pixel (the minimum, when target_stderr is set)
  AoDefinition definition;
  SamplerKind sampler = SamplerKind::sobol;  // Owen-scrambled Sobol: the least error per ray
  uint64_t seed = 1;
  NormalMode normal = NormalMode::shading;  // which normal orients the hemisphere
  double target_stderr = 0.0;               // > 0: keep sampling until stderr <= this ...
  int max_spp = 16384;                      // ... or this many rays
  // A frame of a sequence that advances (rtao): each replicate's points start at sample index
  // `first_sample` of its scrambled sequence (samplers.h), and `replicates` > 0 fixes their
  // number (spp must be a multiple of it; 0: replicate_count(sampler, spp)). The reference's
  // defaults, 0 and 0, give the points it has always drawn.
  uint32_t first_sample = 0;
  int replicates = 0;
};

// Independent replicates used for the standard error of the stratified and sobol samplers (their
// sample variance overestimates the error, so it is measured across independent randomisations).
int replicate_count(SamplerKind sampler, int spp);
// The replicates a trace uses: settings.replicates when set, else replicate_count().
int replicates_of(const AoTraceSettings& settings);

struct TracedAo {
  int width = 0, height = 0;
  std::vector<float> ao;         // AO, in [0, 1]; 0 where not covered
  std::vector<float> stderr_ao;  // standard error of the per-pixel mean
  std::vector<glm::vec3> bent;   // unit mean unoccluded direction; zero if fully occluded
  // The bent normal's own noise: rms angle, degrees, between `bent` and its expectation, from the
  // covariance of the mean vector over the same units as stderr_ao (samples, or replicates for
  // stratified and sobol). Empty when read from a reference file written without it.
  std::vector<float> bent_stderr;
  std::vector<float> coverage;  // A, copied from the G-buffer
  bool covered(size_t k) const { return is_covered(coverage[k]); }
  std::vector<float> spp;    // rays actually used per pixel
  uint64_t rays_traced = 0;  // rays sent to Embree (below-surface directions are not traced)
  uint64_t samples = 0;      // directions evaluated, traced or not
  double seconds = 0.0;
};

// Deterministic: the same settings give the same bits whatever the thread count (each pixel draws
// from its own stream and sums in a fixed order). Each ray stops at the definition's dmax (any hit
// for falloff none): the least work for one definition, what the raytraced and rtao estimators
// time.
TracedAo trace_ao(const EmbreeScene& scene, const GBuffer& gbuffer,
                  const AoTraceSettings& settings);

// The references' trace (issue 42): every definition of `definitions` (one weighting, so one set
// of directions; settings.definition is ignored) from the same rays, one image each with its own
// standard error and bent normal. Every ray finds its closest hit with no bound and each definition
// reads its value from that distance (AoDefinition::ray_value: a hit at or beyond its dmax is a
// miss for it), so a definition's image is the same bits whichever definitions share the trace,
// alone included (a lone unbounded `none` asks rtcOccluded whether anything is hit, which accepts
// exactly the hits rtcIntersect does). Bounded definitions thus cost a closest-hit ray each rather
// than trace_ao's any-hit ray to dmax; in a suite they share the unbounded true-AO trace anyway.
// rays_traced, samples and seconds are the shared trace's, in every image. InputError for mixed
// weightings or adaptive sampling (target_stderr) with more than one definition.
std::vector<TracedAo> trace_ao_definitions(const EmbreeScene& scene, const GBuffer& gbuffer,
                                           const AoTraceSettings& settings,
                                           const std::vector<AoDefinition>& definitions);

// Fills `rays` with every traced occlusion ray of the reference (same directions, same origins),
// for the throughput benchmark's bare Embree loop. Random sampler only.
struct BareRay {
  glm::vec3 origin, direction;
  float tfar;
  // The packet the reference traces this ray in: rays of one pixel's replicate share an origin and
  // go out in packets of 16 in sample order, so consecutive rays with the same packet number form
  // the reference's RTCRay16 (the bench's bare rtcOccluded16 loop replays exactly those packets).
  uint32_t packet;
};
std::vector<BareRay> generate_traced_rays(const GBuffer& gbuffer, const AoTraceSettings& s,
                                          float scene_extent);

}  // namespace aoeval
