// A content-addressed cache of reference images: the key hashes everything the image depends on
// (scene geometry, camera and resolution, definition, spp, sampler, seed, normal mode, adaptive
// target, generator version), so asking twice computes once and any change recomputes.
#pragma once

#include <optional>
#include <string>

#include "references/reference.h"
#include "scenes/camera.h"
#include "scenes/exr_io.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval {

// Bump when the reference's output for the same inputs changes (reference-2: the bent_stderr
// channel, the bent normal's own noise; reference-3: G-buffer hit points from world-space
// barycentrics, as instances need, and bounded definitions read from one closest-hit trace;
// reference-4: ray origins 2^-18 instead of 2^-14 of the position off the surface,
// sampling/ray_offset.cpp).
inline constexpr const char* kReferenceGeneratorVersion = "reference-4";

std::string reference_cache_key(const Scene& scene, const Camera& camera,
                                const ReferenceSettings& settings);
// The same from the scene's content_hash(), for callers that hash a scene once (the session).
std::string reference_cache_key(uint64_t scene_hash, const Camera& camera,
                                const ReferenceSettings& settings);
// <data cache>/references/<key>.exr
std::string reference_cache_path(const std::string& key);

// The EXR header of a reference image (CONTRACT: aoeval:scene, view, camera, definition, spp,
// sampler, seed, estimator, params, version): one definition for `aoeval reference` and the
// harness's cache, so a cached file reads the same whoever wrote it.
Attributes reference_attributes(const Scene& scene, const View& view, const Camera& camera,
                                const ReferenceSettings& settings);
Attributes reference_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                                const Camera& camera, const ReferenceSettings& settings);

// Cache entries check themselves. A file in the cache folder can be truncated by a crash of
// another tool, replaced by hand, or be any EXR that happens to carry the name: served blindly, it
// would become the ground truth. So every entry carries its key (aoeval:cache_key) and a checksum
// of its pixels (aoeval:checksum, FNV-1a over every channel's float bits in file order), both
// verified on read.
std::string image_checksum(const OIIO::ImageBuf& image);
// Appends aoeval:cache_key and aoeval:checksum for `image` to `attributes`.
void add_cache_attributes(Attributes& attributes, const std::string& key,
                          const OIIO::ImageBuf& image);
// Why the file at `path` is not a valid entry for `key` (unreadable or truncated, another key, a
// checksum that does not match its pixels, missing channels), or "" when it is valid.
std::string cache_entry_problem(const std::string& path, const std::string& key);
// True when `path` exists and is a valid entry for `key`. A damaged entry is reported on stderr
// ("reference cache: <path>: <problem>; recomputing"), removed, and false is returned, so the
// caller recomputes it.
bool usable_cache_entry(const std::string& path, const std::string& key);
// The entry as a reference image when usable_cache_entry() would say true, read once for both the
// check and the use; nullopt (a damaged entry reported and removed likewise) otherwise.
std::optional<ReferenceImage> read_usable_cache_entry(const std::string& path,
                                                      const std::string& key);

}  // namespace aoeval
