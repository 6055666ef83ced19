// The estimator registry. Registration is explicit: registry.cpp calls each estimator folder's
// declaration function by name, so no estimator can be dropped by the linker or registered twice
// by accident. Adding an estimator = one add_subdirectory line and one line in registry.cpp.
#pragma once

#include <string>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

const std::vector<EstimatorInfo>& estimator_registry();
// InputError listing the known estimators when `name` is unknown.
const EstimatorInfo& find_estimator(const std::string& name);

}  // namespace aoeval
