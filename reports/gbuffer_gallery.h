// The G-buffer gallery: normal and depth previews of every scene view, on one HTML page. Reads the
// G-buffer EXRs the harness wrote; runs nothing.
#pragma once

#include <string>
#include <vector>

#include "harness/results/suite_record.h"

namespace aoeval {

// Writes `out_dir`/index.html, and the PNG previews beside each EXR that lacks them (the suite
// runner writes them as it goes; drawing/gbuffer_previews.h); returns the page's path.
std::string write_gbuffer_gallery(const std::string& out_dir, const std::string& suite,
                                  const std::vector<GalleryEntry>& entries);

}  // namespace aoeval
