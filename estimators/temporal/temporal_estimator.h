// An estimator accumulated over time by the shared temporal stage (temporal_stage.h): wraps an
// estimator whose frames are each their own estimate (gtao with its rotated noise, Jimenez et al.
// 2016 §5.2) and feeds each frame's AO through a TemporalAccumulator, so that the rotated frames
// are averaged where the paper averages them (its temporal reprojection) rather than by the test.
// Per frame: the inner estimator runs; at a still view, at frame 0 and after reset the stage
// starts afresh (the output is the inner estimate bit for bit); otherwise the output is the
// stage's value(). The inner AO is kept as the extra channel AO_frame, the history length as
// history_length; the stage's wall time is pass_ms "temporal_ms" and, where the inner estimator
// times itself (GPU timestamps, "total_ms"), is added to total_ms so the frame time is honest.
#pragma once

#include <memory>

#include "estimators/estimator.h"
#include "estimators/temporal/temporal_stage.h"

namespace aoeval {

std::unique_ptr<Estimator> with_temporal_stage(std::unique_ptr<Estimator> inner,
                                               const TemporalSettings& settings);

}  // namespace aoeval
