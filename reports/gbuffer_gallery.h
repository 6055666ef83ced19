// The G-buffer gallery: normal and depth previews of every scene view, on one HTML page. Reads the
// G-buffer EXRs the harness wrote; runs nothing.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

struct GalleryEntry {
  std::string scene;
  std::string view;
  size_t triangles = 0;
  size_t objects = 0;
  double load_ms = 0.0;
  double bvh_ms = 0.0;
  std::string gbuffer_exr;  // relative to the output folder
};

// Writes PNG previews beside each EXR and `out_dir`/index.html; returns the page's path.
std::string write_gbuffer_gallery(const std::string& out_dir, const std::string& suite,
                                  const std::vector<GalleryEntry>& entries);

// Previews of one G-buffer file: normals as RGB (n * 0.5 + 0.5) and linear depth through the
// "inferno" colour map (near = bright), normalised over covered pixels; background dark grey.
void write_gbuffer_previews(const std::string& gbuffer_exr, const std::string& normals_png,
                            const std::string& depth_png);

}  // namespace aoeval
