// Previews of a G-buffer EXR for the gallery page (reports/gbuffer_gallery.h): drawn by the
// suite runner in the background as each view is first rendered, and by the page for any view
// whose previews are missing (a run merged from shards).
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <string>

namespace aoeval {

// "<dir>/<stem>_normals.png" and "<dir>/<stem>_depth.png" beside "<dir>/<stem>.exr".
struct GBufferPreviewPaths {
  std::string normals, depth;
};
GBufferPreviewPaths gbuffer_preview_paths(const std::string& gbuffer_exr);

// Previews of one G-buffer file: normals as RGB (n * 0.5 + 0.5) and linear depth through the
// "inferno" colour map (near = bright), normalised over covered pixels; background dark grey.
void write_gbuffer_previews(const std::string& gbuffer_exr, const std::string& normals_png,
                            const std::string& depth_png);
// The same from the image that was (or is being) written to `gbuffer_exr` (float channels, so the
// file holds the same values): the suite runner does not read back the file it just wrote.
void write_gbuffer_previews(const OIIO::ImageBuf& gbuffer, const std::string& gbuffer_exr,
                            const std::string& normals_png, const std::string& depth_png);

}  // namespace aoeval
