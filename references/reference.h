// The Embree reference generator: per-pixel ground-truth AO at the shared G-buffer's surface
// points, with its own per-pixel standard error, so that comparisons can tell noise from error (in
// the spirit of Mitsuba 3's statistical render tests). The tracing is sampling/ao_tracer.h's; this
// is the reference's image files, options and parameters.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sampling/ao_tracer.h"
#include "scenes/ao_definition.h"
#include "scenes/ao_exr.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {

// The reference's types are the tracer's (sampling/ao_tracer.h): the settings with their
// defaults, and the traced image, also read back from reference EXRs.
using ReferenceSettings = AoTraceSettings;
using ReferenceImage = TracedAo;

// The ground truth: trace_ao_definitions with the reference's settings and its one definition,
// the same bits as when it shares its rays with other definitions (compute_references).
inline ReferenceImage compute_reference(const EmbreeScene& scene, const GBuffer& gbuffer,
                                        const ReferenceSettings& settings) {
  return std::move(trace_ao_definitions(scene, gbuffer, settings, {settings.definition})[0]);
}

// Several definitions of one weighting from one trace (settings.definition ignored): image i is
// compute_reference of definitions[i], bit for bit.
inline std::vector<ReferenceImage> compute_references(
    const EmbreeScene& scene, const GBuffer& gbuffer, const ReferenceSettings& settings,
    const std::vector<AoDefinition>& definitions) {
  return trace_ao_definitions(scene, gbuffer, settings, definitions);
}

// Frame k of a sequence (CONTRACT §10) is traced with seed + k, so that consecutive frames'
// references are independent samples: the temporal scores remove the reference's noise as
// stderr_k^2 + stderr_{k-1}^2, which is the variance of ref_k - ref_{k-1} only when their noise is
// independent (one seed for all frames would repeat a static pixel's noise exactly).
inline ReferenceSettings frame_reference_settings(ReferenceSettings s, int frame) {
  s.seed += static_cast<uint64_t>(frame);
  return s;
}

// origin_offset (sampling/ray_offset.h): where the reference's rays start.

// The reference as an EXR image (channels AO, AO_stderr, bent.X/Y/Z, A, bent_stderr, and spp when
// adaptive).
OIIO::ImageBuf reference_to_image(const ReferenceImage& r, bool with_spp);
// The effective settings as JSON (the aoeval:params attribute).
nlohmann::json reference_params(const ReferenceSettings& s);
void parse_reference_options(ReferenceSettings& s, const std::string& weighting,
                             const std::string& dmax, const std::string& falloff,
                             const std::string& sampler, const std::string& normal);

// The reference's traced rays (generate_traced_rays), for the throughput benchmark's bare loops.
inline std::vector<BareRay> generate_reference_rays(const GBuffer& gbuffer,
                                                    const ReferenceSettings& s,
                                                    float scene_extent) {
  return generate_traced_rays(gbuffer, s, scene_extent);
}

}  // namespace aoeval

namespace aoeval {
// Reads a reference EXR written by reference_to_image (bent normals and spp optional).
ReferenceImage read_reference_image(const std::string& path);
ReferenceImage reference_image_from(AoExr file);
}  // namespace aoeval
