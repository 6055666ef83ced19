#include "harness/sweep/kept_references.h"

#include <filesystem>

#include "harness/results/result_row.h"
#include "references/reference_cache.h"
#include "scenes/text_files.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string KeptReferences::keep(EvaluationSession& session, const std::string& scene_name,
                                 const View& view, int w, int h, const AoDefinition& definition) {
  const auto& data = session.scene(scene_name);
  const Scene& scene = data.scene;
  const ReferenceSpec& spec = session.reference_spec();
  const std::string rel =
      "references/" +
      file_stem_for(scene.name + "/" + view.name + "/" + std::to_string(w) + "x" +
                    std::to_string(h) + "/" + definition.label() +
                    "/spp:" + std::to_string(spec.spp) + "/" + sampler_name(spec.sampler) +
                    "/seed:" + std::to_string(spec.seed)) +
      ".exr";
  if (!written_.insert(rel).second) return rel;
  session.reference(scene_name, view, w, h, definition);  // computes or reads the cache
  // The cache entry session.reference() used: for a sequence view that is its still frame (the
  // last one, whose estimate the row keeps), posed scene, camera and seed + k included.
  const int k = EvaluationSession::still_frame(view);
  const std::string cached = reference_cache_path(reference_cache_key(
      session.frame_scene(scene_name, view, k).content_hash,
      session.gbuffer(scene_name, view, w, h).camera, session.frame_settings(view, k, definition)));
  const fs::path target = fs::path(out_) / rel;
  fs::create_directories(target.parent_path());
  const std::string temp = temporary_path_for(target.string());  // one naming: leftovers are found
  fs::copy_file(cached, temp, fs::copy_options::overwrite_existing);
  commit_temporary(temp, target.string());
  return rel;
}

}  // namespace aoeval
