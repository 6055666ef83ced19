#include "drawing/gbuffer_previews.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <filesystem>

#include "scenes/exr_io.h"

namespace aoeval {

namespace {
const float kBackground = 0.12f;
}  // namespace

GBufferPreviewPaths gbuffer_preview_paths(const std::string& gbuffer_exr) {
  const std::filesystem::path exr(gbuffer_exr);
  const std::string stem = (exr.parent_path() / exr.stem()).string();
  return {stem + "_normals.png", stem + "_depth.png"};
}

void write_gbuffer_previews(const std::string& gbuffer_exr, const std::string& normals_png,
                            const std::string& depth_png) {
  write_gbuffer_previews(read_image(gbuffer_exr), gbuffer_exr, normals_png, depth_png);
}

void write_gbuffer_previews(const OIIO::ImageBuf& g, const std::string& gbuffer_exr,
                            const std::string& normals_png, const std::string& depth_png) {
  const int a = channel_index(g, "A", gbuffer_exr), z = channel_index(g, "Z", gbuffer_exr);
  const int nx = channel_index(g, "N.X", gbuffer_exr);
  const int w = g.spec().width, h = g.spec().height;
  const auto* px = static_cast<const float*>(g.localpixels());
  const int nc = g.spec().nchannels;

  float zmin = 1e30f, zmax = -1e30f;
  for (long k = 0; k < static_cast<long>(w) * h; ++k) {
    if (px[k * nc + a] < 0.5f) continue;
    zmin = std::min(zmin, px[k * nc + z]);
    zmax = std::max(zmax, px[k * nc + z]);
  }
  const float zrange = zmax > zmin ? zmax - zmin : 1.0f;

  OIIO::ImageBuf normals(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBuf depth(OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBuf mask(OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT));
  auto* np = static_cast<float*>(normals.localpixels());
  auto* dp = static_cast<float*>(depth.localpixels());
  auto* mp = static_cast<float*>(mask.localpixels());
  for (long k = 0; k < static_cast<long>(w) * h; ++k) {
    const bool covered = px[k * nc + a] >= 0.5f;
    mp[k] = covered ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c)
      np[k * 3 + c] = covered ? px[k * nc + nx + c] * 0.5f + 0.5f : kBackground;
    dp[k] = covered ? 1.0f - (px[k * nc + z] - zmin) / zrange : 0.0f;
  }
  // OIIO's colour map gives linear values; PNG holds sRGB-encoded ones. Then the background is
  // painted where A = 0.
  OIIO::ImageBuf coloured = OIIO::ImageBufAlgo::colorconvert(
      OIIO::ImageBufAlgo::color_map(depth, 0, "inferno"), "linear", "sRGB");
  auto* cp = static_cast<float*>(coloured.localpixels());
  for (long k = 0; k < static_cast<long>(w) * h; ++k)
    if (mp[k] < 0.5f)
      for (int c = 0; c < 3; ++c) cp[k * 3 + c] = kBackground;
  write_image(normals_png, normals);
  write_image(depth_png, coloured);
}

}  // namespace aoeval
