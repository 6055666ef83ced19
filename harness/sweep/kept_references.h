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

 private:
  std::string out_;
  std::set<std::string> written_;
};

}  // namespace aoeval
