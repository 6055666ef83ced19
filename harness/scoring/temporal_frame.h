// Frame k of a sequence as TemporalScorer reads it (temporal.h), built one way for the session's
// frames (harness/evaluation/frames.cpp) and `compare --sequence`'s (cmd/compare_sequence.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "harness/scoring/temporal.h"
#include "scenes/gbuffer.h"

namespace aoeval {

// `est` and `ref` are width x height; `ref_stderr` the reference's per-pixel standard error
// (empty: 0); `compared` 1 where the pixel is compared. `motion`: frame k's G-buffer with its
// motion.X/Y and disoccluded channels (null, or one without them: nothing moves).
// `prev_jitter`: frame k - 1's camera jitter (zero for frame 0). The pointers stay the callers'.
inline TemporalFrame temporal_frame(int width, int height, const float* est, const float* ref,
                                    const std::vector<float>& ref_stderr,
                                    const std::vector<uint8_t>& compared, const GBuffer* motion,
                                    glm::vec2 prev_jitter, bool ref_repeats_previous = false) {
  TemporalFrame tf;
  tf.width = width;
  tf.height = height;
  tf.est = est;
  tf.ref = ref;
  tf.ref_stderr = ref_stderr.empty() ? nullptr : ref_stderr.data();
  tf.compared = compared.data();
  tf.motion = motion && !motion->motion.empty() ? &motion->motion[0].x : nullptr;
  tf.disoccluded = motion && !motion->disoccluded.empty() ? motion->disoccluded.data() : nullptr;
  tf.prev_jitter_x = prev_jitter.x;
  tf.prev_jitter_y = prev_jitter.y;
  tf.ref_repeats_previous = ref_repeats_previous;
  return tf;
}

}  // namespace aoeval
