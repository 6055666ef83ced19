// A content-addressed cache of reference images: the key hashes everything the image depends on
// (scene geometry, camera and resolution, definition, spp, sampler, seed, normal mode, adaptive
// target, generator version), so asking twice computes once and any change recomputes.
#pragma once

#include <optional>
#include <string>

#include "camera.h"
#include "gbuffer.h"
#include "references/reference.h"
#include "scene.h"

namespace aoeval {

// Bump when the reference's output for the same inputs changes (reference-2: the bent_stderr
// channel, the bent normal's own noise).
inline constexpr const char* kReferenceGeneratorVersion = "reference-2";

std::string reference_cache_key(const Scene& scene, const Camera& camera,
                                const ReferenceSettings& settings);
// <data cache>/references/<key>.exr
std::string reference_cache_path(const std::string& key);

// The EXR header of a reference image (CONTRACT: aoeval:scene, view, camera, definition, spp,
// sampler, seed, estimator, params, version): one definition for `aoeval reference` and the
// harness's cache, so a cached file reads the same whoever wrote it.
Attributes reference_attributes(const Scene& scene, const View& view, const Camera& camera,
                                const ReferenceSettings& settings);

}  // namespace aoeval
