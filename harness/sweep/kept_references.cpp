#include "harness/sweep/kept_references.h"

#include <cstdio>
#include <filesystem>

#include "base/text_files.h"
#include "harness/results/result_row.h"
#include "references/reference_cache.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string frame_file_name(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.exr", frame);
  return name;
}

std::string KeptReferences::stem(EvaluationSession& session, const std::string& scene_name,
                                 const View& view, int w, int h,
                                 const AoDefinition& definition) const {
  const Scene& scene = session.scene(scene_name).scene;
  const ReferenceSpec& spec = session.reference_spec();
  return "references/" +
         file_stem_for(scene.name + "/" + view.name + "/" + std::to_string(w) + "x" +
                       std::to_string(h) + "/" + definition.label() +
                       "/spp:" + std::to_string(spec.spp) + "/" + sampler_name(spec.sampler) +
                       "/seed:" + std::to_string(spec.seed));
}

void KeptReferences::copy(const std::string& from, const std::string& rel) {
  const fs::path target = fs::path(out_) / rel;
  fs::create_directories(target.parent_path());
  const std::string temp = temporary_path_for(target.string());  // one naming: leftovers are found
  fs::copy_file(from, temp, fs::copy_options::overwrite_existing);
  commit_temporary(temp, target.string());
}

std::string KeptReferences::keep(EvaluationSession& session, const std::string& scene_name,
                                 const View& view, int w, int h, const AoDefinition& definition) {
  const std::string rel = stem(session, scene_name, view, w, h, definition) + ".exr";
  if (!written_.insert(rel).second) return rel;
  session.reference(scene_name, view, w, h, definition);  // computes or reads the cache
  // The cache entry session.reference() used: for a sequence view that is its still frame (the
  // last one, whose estimate the row keeps), posed scene, camera and seed + k included.
  const int k = EvaluationSession::still_frame(view);
  copy(reference_cache_path(
           reference_cache_key(session.frame_scene(scene_name, view, k).content_hash,
                               session.gbuffer(scene_name, view, w, h).camera,
                               session.frame_settings(scene_name, view, k, definition))),
       rel);
  return rel;
}

std::string KeptReferences::keep_frame(EvaluationSession& session, const std::string& scene_name,
                                       const View& view, int w, int h,
                                       const AoDefinition& definition, int frame,
                                       const std::string& cache_path) {
  const std::string rel =
      stem(session, scene_name, view, w, h, definition) + "/" + frame_file_name(frame);
  if (written_.insert(rel).second) copy(cache_path, rel);
  return rel;
}

}  // namespace aoeval
