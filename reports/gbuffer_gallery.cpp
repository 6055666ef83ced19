#include "reports/gbuffer_gallery.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "drawing/gbuffer_previews.h"
#include "reports/html.h"
#include "reports/page_assets.h"
#include "reports/viewer.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {
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

std::string write_gbuffer_gallery(const std::string& out_dir, const std::string& suite,
                                  const std::vector<GalleryEntry>& entries) {
  Html html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
       << content_security_policy() << "<title>aoeval " << text(suite)
       << " suite: scene corpus G-buffers</title>\n"
       << page_stylesheet(out_dir, "gallery.css") << write_viewer_assets(out_dir)
       << "</head><body>\n"
       << "<h1>aoeval: " << text(suite) << " suite</h1>\n"
       << "<p>The shared G-buffer of every corpus scene and view: shading normals (RGB = N &times; "
          "0.5 + "
          "0.5) and linear view depth (inferno colour map, near = bright). Each image links to its "
          "OpenEXR file (channels A, Z, P, N, Ng, objectId). The suite's report (references, "
          "estimates, errors, timings) is <a href=\"../index.html\">../index.html</a>. A view's "
          "images open in the viewer (click them): zoom to pixels and read N, Z and A under the "
          "cursor.</p>\n";
  html << "<table><tr><th>scene</th><th>triangles</th><th>objects</th><th>load ms</th><th>BVH "
          "ms</th></tr>\n";
  std::string last;
  for (const auto& e : entries) {
    if (e.scene == last) continue;
    last = e.scene;
    html << "<tr><th><a href=\"#" << attr(e.scene) << "\">" << text(e.scene) << "</a></th><td>"
         << text(with_commas(e.triangles)) << "</td><td>" << e.objects << "</td><td>"
         << static_cast<long>(e.load_ms) << "</td><td>" << static_cast<long>(e.bvh_ms)
         << "</td></tr>\n";
  }
  html << "</table>\n";
  last.clear();
  for (const auto& e : entries) {
    if (e.scene != last) {
      if (!last.empty()) html << "</section>\n";
      html << "<section id=\"" << attr(e.scene) << "\"><h2>" << text(e.scene) << "</h2>"
           << "<p>" << text(with_commas(e.triangles)) << " triangles, " << e.objects
           << " object(s)</p>\n";
      last = e.scene;
    }
    const auto [normals, depth] = gbuffer_preview_paths(e.gbuffer_exr);
    const fs::path exr = fs::path(out_dir) / e.gbuffer_exr;
    const fs::path normals_png = fs::path(out_dir) / normals, depth_png = fs::path(out_dir) / depth;
    std::error_code error;
    const auto exr_time = fs::last_write_time(exr, error);
    auto stale = [&](const fs::path& png) {
      std::error_code e2;
      const auto t = fs::last_write_time(png, e2);
      return e2 || error || t < exr_time;
    };
    if (stale(normals_png) || stale(depth_png))
      write_gbuffer_previews(exr.string(), normals_png.string(), depth_png.string());
    Html figures;
    for (const auto& [img, label] :
         {std::pair<std::string, std::string>{normals, "normals"}, {depth, "depth"}}) {
      figures << "<figure><a href=\"" << url(e.gbuffer_exr) << "\"><img src=\"" << url(img)
              << "\" loading=\"lazy\" alt=\"" << attr(e.scene + " " + e.view + " " + label)
              << "\"></a><figcaption>" << text(e.view + ": " + label) << "</figcaption></figure>\n";
    }
    ViewerSpec viewer;  // the same pictures from the EXR's floats, with the probe (CONTRACT §11)
    viewer.kind = "gbuffer";
    viewer.a = write_viewer_data(out_dir, {e.gbuffer_exr}, gbuffer_viewer_channels());
    html << viewer_html(viewer, figures);
  }
  if (!last.empty()) html << "</section>\n";
  html << "</body></html>\n";
  const std::string page = (fs::path(out_dir) / "index.html").string();
  write_text(page, html.str());
  return page;
}

}  // namespace aoeval
