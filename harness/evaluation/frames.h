// What crosses from measure() to score() for one frame (frames.cpp, evaluation.cpp): internal to
// harness/evaluation/.
#pragma once

#include <memory>

#include "harness/evaluation/evaluation.h"
#include "harness/scoring/temporal_frame.h"

namespace aoeval {

struct EvaluationSession::FrameToScore {
  int index = 0;  // the frame's number (0 for a still)
  const GBuffer* gbuffer = nullptr;
  const EstimateResult* estimate = nullptr;
  const ReferenceImage* matched = nullptr;
  const ReferenceImage* truth = nullptr;  // the matched one itself when its definition is true AO
  // A sequence frame's references' cache keys (the same key, the same image): the other points of
  // the view share FLIP's reference side by them (ReferenceStore::flip_frame_reference).
  std::string matched_key = {}, truth_key = {};
  double time_ms = 0.0;               // a sequence frame's timed run
  bool ref_repeats_previous = false;  // TemporalFrame's
  glm::vec2 prev_jitter{0.0f};        // frame k - 1's camera jitter
  bool last = true;  // the row's plain metrics are the last frame's (still_frame())
};

// A sequence's scoring state: its temporal scorers and frames.csv rows (filled frame by frame, in
// order, on the thread that scores them), and until score() its last frame's G-buffer, references
// and timing.
struct SequenceScoring {
  TemporalScorer matched_scores, true_scores;
  std::vector<nlohmann::json> frames;
  std::shared_ptr<const GBuffer> gbuffer;
  std::shared_ptr<const ReferenceImage> matched;
  std::shared_ptr<const ReferenceImage> truth;  // when it is not the matched one
  EvaluationSession::FrameToScore frame;        // its pointers set by score()
};

}  // namespace aoeval
