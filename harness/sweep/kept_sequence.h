// What a sequence point (CONTRACT §10) keeps besides its row, for its report section (strip,
// video, charts, the viewer's frames) and for `aoeval compare --sequence`. Under the point's
// folder <out>/<base>/sequences/<file_stem_for(run name)>/ (base "" for a sweep, runs/<run id>
// for a suite run):
//   frame_KKKK.exr   the estimate of each kept frame (kept_sequence_frames(): at most
//                    kMaxKeptFrames, float AO and A as the row's estimate EXR; unless
//                    `references.exact()`, at float16 precision as the kept references are, and
//                    AO and A only: the estimator's extra channels, e.g. a bent normal, are in
//                    the row's estimate EXR), so a point costs at most 48 still estimates on disk
//   sequence.json    the report's manifest: frames, fps, the kept frames with their estimate and
//                    reference EXRs (relative to <out>), rmse_excess by frame (matched, and
//                    true_rmse_excess by frame) and by frames since disocclusion, disoccluded
//                    pixels by frame, "maps": maps.exr's path (relative to <out>) when kept
//   maps.exr         the flicker and lag maps (harness/scoring/temporal.h): channels flicker,
//                    lag and A (1 where the flicker map has a value), 0 where a map never counted
//   frames.csv       one line per frame (results_store.h)
// and each kept frame's matched reference, kept (kept_references.h) from the cache entry it was
// scored against, to <out>/references/<the still reference's name>/frame_KKKK.exr (once per run:
// points of one view share them; a frame that reuses its predecessor's entry is a hard link). Every
// file is written atomically, and all of them before the row is committed: a committed row has all
// of its files, and a point killed before its row is redone whole by
// --resume, which rewrites them.
#pragma once

#include <string>
#include <vector>

#include "harness/evaluation/evaluation.h"
#include "harness/results/point_record.h"
#include "harness/sweep/kept_references.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {

// `keep_frames` false (a sweep's --no-estimates): sequence.json and frames.csv only, no EXRs.
// Returns the files kept, paths relative to <out> (roles "frame KKKK estimate", "frame KKKK
// reference", "maps", then "sequence" and "frames": point_record.h), for the point's record.
std::vector<KeptImage> keep_sequence(const std::string& out, const std::string& base,
                                     const SweepPoint& p, const Measurement& m,
                                     EvaluationSession& session, KeptReferences& references,
                                     bool keep_frames = true);

}  // namespace aoeval
