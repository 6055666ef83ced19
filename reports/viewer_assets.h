// The viewer's JavaScript and CSS (reports/viewer/*), compiled into the binary by CMake
// (reports/CMakeLists.txt generates viewer_assets.cpp from them), so `aoeval` stays one file.
#pragma once

#include <string_view>
#include <vector>

namespace aoeval {

struct ViewerAsset {
  std::string_view name;     // "viewer.js"
  std::string_view content;  // the file's bytes
};
const std::vector<ViewerAsset>& viewer_assets();

}  // namespace aoeval
