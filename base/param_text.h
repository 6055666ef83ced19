// The stable text of a parameter value, used in run names, results and reports alike (estimators/
// declares parameters; results/ and reports/ print them): 0.2, 8, true, cosine. Numbers take the
// shortest form that reads back as the same double.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace aoeval {

std::string format_param_value(const nlohmann::json& value);

}  // namespace aoeval
