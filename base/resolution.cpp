#include "base/resolution.h"

#include <cstdlib>

#include "base/errors.h"

namespace aoeval {

std::pair<int, int> parse_resolution(const std::string& text, const std::string& option) {
  if (text.empty()) return {0, 0};
  const auto x = text.find('x');
  auto bad = [&]() -> std::pair<int, int> {
    throw InputError(option + ": expected WIDTHxHEIGHT with each in [1, 16384], got '" + text +
                     "'");
  };
  if (x == std::string::npos) return bad();
  const std::string w = text.substr(0, x), h = text.substr(x + 1);
  if (w.empty() || h.empty() || w.find_first_not_of("0123456789") != std::string::npos ||
      h.find_first_not_of("0123456789") != std::string::npos || w.size() > 5 || h.size() > 5)
    return bad();
  const int wi = std::atoi(w.c_str()), hi = std::atoi(h.c_str());
  if (wi < 1 || hi < 1 || wi > 16384 || hi > 16384) return bad();
  return {wi, hi};
}

}  // namespace aoeval
