// raytraced: the reference algorithm itself (sampling/ao_tracer.h, the ground truth's tracer)
// the cost/accuracy yardstick every approximation must beat. Its parameters choose the AO
// definition it estimates (weighting, dmax, falloff), so it can be matched to any other estimator.
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo raytraced_estimator();

}  // namespace aoeval
