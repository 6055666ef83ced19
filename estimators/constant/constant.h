// constant: AO = a constant everywhere, 1 by default: the "ambient only" shading of Hegeman et al.
// 2006, Fig. 12 (bottom row). The floor every estimator must beat.
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo constant_estimator();

}  // namespace aoeval
