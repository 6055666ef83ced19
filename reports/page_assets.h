// The pages' own stylesheets and scripts (reports/pages/: suite.css, dashboard.css, gallery.css,
// figures.css, dashboard.js) as real files, not C++ strings: built into the binary like the
// viewer's (viewer_assets.h) and written beside the page that uses them.
#pragma once

#include <filesystem>
#include <string>

#include "reports/html.h"

namespace aoeval {

// Writes reports/pages/NAME to <page_dir>/NAME, atomically and only when it differs.
// std::logic_error when no such file was built in.
void write_page_asset(const std::string& page_dir, const std::string& name);
// write_page_asset, then the <link rel="stylesheet"> tag for the page's <head>.
Html page_stylesheet(const std::string& page_dir, const std::string& name);

// Rewrites `path` only when its content differs, so an unchanged asset keeps its time stamp.
void write_if_changed(const std::filesystem::path& path, const std::string& content);

}  // namespace aoeval
