// raytraced: the reference algorithm itself (references/reference.h) with `rays` rays per pixel:
// the cost/accuracy yardstick every approximation must beat. Its parameters choose the AO
// definition it estimates (weighting, dmax, falloff), so it can be matched to any other estimator.
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo raytraced_estimator();

}  // namespace aoeval
