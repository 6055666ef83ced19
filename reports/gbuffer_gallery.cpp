#include "gbuffer_gallery.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "exr_io.h"
#include "reports/html.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {
const float kBackground = 0.12f;

std::string with_commas(size_t n) {
  const std::string digits = std::to_string(n);
  std::string s;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s.push_back(',');
    s.push_back(digits[i]);
  }
  return s;
}
}  // namespace

void write_gbuffer_previews(const std::string& gbuffer_exr, const std::string& normals_png,
                            const std::string& depth_png) {
  OIIO::ImageBuf g = read_image(gbuffer_exr);
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

std::string write_gbuffer_gallery(const std::string& out_dir, const std::string& suite,
                                  const std::vector<GalleryEntry>& entries) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
       << "<title>aoeval " << html_escape(suite) << " suite: scene corpus G-buffers</title>\n"
       << "<style>body{font-family:sans-serif;margin:1.5em;background:#fafafa;color:#222}"
          "section{margin-bottom:1.5em;border-bottom:1px solid #ddd;padding-bottom:1em}"
          "figure{display:inline-block;margin:0 1em 0.5em 0;vertical-align:top}"
          "figcaption{font-size:0.85em;color:#555}img{image-rendering:pixelated;border:1px solid "
          "#ccc}"
          "table{border-collapse:collapse}td,th{padding:2px 10px;text-align:right}"
          "th{text-align:left}</style></head><body>\n"
       << "<h1>aoeval: " << html_escape(suite) << " suite</h1>\n"
       << "<p>The shared G-buffer of every corpus scene and view: shading normals (RGB = N &times; "
          "0.5 + "
          "0.5) and linear view depth (inferno colour map, near = bright). Each image links to its "
          "OpenEXR file (channels A, Z, P, N, Ng, objectId). The suite's report (references, "
          "estimates, errors, timings) is <a href=\"../index.html\">../index.html</a>.</p>\n";
  html << "<table><tr><th>scene</th><th>triangles</th><th>objects</th><th>load ms</th><th>BVH "
          "ms</th></tr>\n";
  std::string last;
  for (const auto& e : entries) {
    if (e.scene == last) continue;
    last = e.scene;
    html << "<tr><th><a href=\"#" << html_escape(e.scene) << "\">" << html_escape(e.scene)
         << "</a></th><td>" << with_commas(e.triangles) << "</td><td>" << e.objects << "</td><td>"
         << static_cast<long>(e.load_ms) << "</td><td>" << static_cast<long>(e.bvh_ms)
         << "</td></tr>\n";
  }
  html << "</table>\n";
  last.clear();
  for (const auto& e : entries) {
    if (e.scene != last) {
      if (!last.empty()) html << "</section>\n";
      html << "<section id=\"" << html_escape(e.scene) << "\"><h2>" << html_escape(e.scene)
           << "</h2>"
           << "<p>" << with_commas(e.triangles) << " triangles, " << e.objects
           << " object(s)</p>\n";
      last = e.scene;
    }
    const fs::path exr(e.gbuffer_exr);
    const std::string stem = (exr.parent_path() / exr.stem()).string();
    const std::string normals = stem + "_normals.png", depth = stem + "_depth.png";
    write_gbuffer_previews((fs::path(out_dir) / e.gbuffer_exr).string(),
                           (fs::path(out_dir) / normals).string(),
                           (fs::path(out_dir) / depth).string());
    for (const auto& [img, label] : {std::pair{normals, "normals"}, std::pair{depth, "depth"}}) {
      html << "<figure><a href=\"" << html_escape(e.gbuffer_exr) << "\"><img src=\""
           << html_escape(img) << "\" alt=\"" << html_escape(e.scene + " " + e.view + " " + label)
           << "\"></a><figcaption>" << html_escape(e.view) << ": " << label
           << "</figcaption></figure>\n";
    }
  }
  if (!last.empty()) html << "</section>\n";
  html << "</body></html>\n";
  const std::string page = (fs::path(out_dir) / "index.html").string();
  write_text(page, html.str());
  return page;
}

}  // namespace aoeval
