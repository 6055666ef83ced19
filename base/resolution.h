// Resolution text of the command line and the specs (CONTRACT §2, §5): "640x480".
#pragma once

#include <string>
#include <utility>

namespace aoeval {

// The --res of the bench commands when none is given (bench estimators, rtao, twin, plug-ins).
inline constexpr const char* kDefaultBenchResolution = "640x480";

// "640x480" -> {640, 480}; {0, 0} for "". InputError naming `option` otherwise (each side in
// [1, 16384]).
std::pair<int, int> parse_resolution(const std::string& text, const std::string& option = "--res");

}  // namespace aoeval
