// The G-buffer gallery: normal and depth previews of every scene view, on one HTML page. Reads the
// G-buffer EXRs the harness wrote; runs nothing.
#pragma once

#include <string>
#include <vector>

#include "harness/results/suite_record.h"

namespace aoeval {

// Writes PNG previews beside each EXR and `out_dir`/index.html; returns the page's path.
std::string write_gbuffer_gallery(const std::string& out_dir, const std::string& suite,
                                  const std::vector<GalleryEntry>& entries);

// Previews of one G-buffer file: normals as RGB (n * 0.5 + 0.5) and linear depth through the
// "inferno" colour map (near = bright), normalised over covered pixels; background dark grey.
void write_gbuffer_previews(const std::string& gbuffer_exr, const std::string& normals_png,
                            const std::string& depth_png);

}  // namespace aoeval
