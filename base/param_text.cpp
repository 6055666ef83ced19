#include "base/param_text.h"

#include <charconv>

namespace aoeval {

std::string format_param_value(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
  if (v.is_number()) {  // shortest text that reads back as the same double: 0.2, not 0.200000
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof(buf), v.get<double>());
    return std::string(buf, r.ptr);
  }
  return v.dump();
}

}  // namespace aoeval
