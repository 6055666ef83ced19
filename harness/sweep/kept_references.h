// The references a run's rows were scored against, kept in its output folder (references/), so
// that its report (mosaics, the viewer) and `aoeval merge` find them without the cache. Used by the
// suite runner and the sweep runner.
#pragma once

#include <set>
#include <string>

#include "harness/evaluation/evaluation.h"

namespace aoeval {

class KeptReferences {
 public:
  explicit KeptReferences(std::string out) : out_(std::move(out)) {}
  // The reference EXR for (scene, view, resolution, definition) under <out>/references/, copied
  // (atomically, once per run) from the content-addressed cache the session filled; returns its
  // path relative to the output folder.
  std::string keep(EvaluationSession& session, const std::string& scene_name, const View& view,
                   int w, int h, const AoDefinition& definition);
  // Frame k of a sequence view's reference, copied from `cache_path` (the entry its frame was
  // scored against, KeptFrame::reference_cache) to references/<keep()'s name>/frame_KKKK.exr, the
  // layout `aoeval compare --sequence` reads; returns that path relative to the output folder.
  std::string keep_frame(EvaluationSession& session, const std::string& scene_name,
                         const View& view, int w, int h, const AoDefinition& definition, int frame,
                         const std::string& cache_path);

 private:
  std::string stem(EvaluationSession& session, const std::string& scene_name, const View& view,
                   int w, int h, const AoDefinition& definition) const;
  void copy(const std::string& from, const std::string& rel);
  std::string out_;
  std::set<std::string> written_;
};

// "frame_0007.exr": the name of frame k in a frame folder (kept estimates and references, and
// what `aoeval compare --sequence` reads).
std::string frame_file_name(int frame);

}  // namespace aoeval
