// The viewer's JavaScript and CSS (reports/viewer/*) and the pages' own stylesheets and scripts
// (reports/pages/*), compiled into the binary by CMake (reports/CMakeLists.txt generates
// viewer_assets.cpp and page_assets_embedded.cpp from them), so `aoeval` stays one file.
#pragma once

#include <string_view>
#include <vector>

namespace aoeval {

struct ViewerAsset {
  std::string_view name;     // "viewer.js"
  std::string_view content;  // the file's bytes
};
const std::vector<ViewerAsset>& viewer_assets();  // reports/viewer/ (write_viewer_assets)
const std::vector<ViewerAsset>& page_assets();    // reports/pages/ (page_assets.h)

}  // namespace aoeval
