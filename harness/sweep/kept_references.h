// The references a run's rows were scored against, kept in its output folder (references/), so
// that its report (mosaics, the viewer) and `aoeval merge` find them without the cache. Used by the
// suite runner and the sweep runner.
//
// Compact by default (issue 42: the default suite's references/ was 431 MB): a kept EXR holds
// every value rounded to float16 precision (10 mantissa bits: within 4.9e-4 of the cache's floats
// for values in [0, 1], far inside a reference's own stderr) and is still a 32-bit float, zip
// compressed EXR (CONTRACT §4), about 1.6x smaller than the noisy float32s (12 of the
// default suite's still references: 16.5 MB -> 10.4 MB). The viewer's compact
// data are float16 too, so its probe returns exactly the kept file's values. A frame whose cache
// entry is one already kept (a frame that does not change reuses its predecessor's reference) is
// a hard link to that file, not a second copy. `exact` (`aoeval sweep`, `aoeval run
// --viewer-exact`): bit-for-bit copies of the cache entries, as before.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <map>
#include <set>
#include <string>

#include "harness/evaluation/evaluation.h"

namespace aoeval {

class KeptReferences {
 public:
  explicit KeptReferences(std::string out, bool exact = false)
      : out_(std::move(out)), exact_(exact) {}
  bool exact() const { return exact_; }
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
  bool exact_ = false;
  std::set<std::string> written_;
  std::map<std::string, std::string> kept_from_;  // cache entry -> the file kept from it
};

// `image` with every value rounded to the nearest float16 (round to nearest even; a value beyond
// float16's range is kept as it is), still float32: what the compact kept files hold.
OIIO::ImageBuf at_half_precision(const OIIO::ImageBuf& image);

// "frame_0007.exr": the name of frame k in a frame folder (kept estimates and references, and
// what `aoeval compare --sequence` reads).
std::string frame_file_name(int frame);

}  // namespace aoeval
