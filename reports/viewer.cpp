#include "reports/viewer.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "base/errors.h"
#include "harness/results/result_row.h"
#include "reports/html.h"
#include "reports/viewer_assets.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Rewrites `path` only when its content differs, so an unchanged asset keeps its time stamp.
void write_if_changed(const fs::path& path, const std::string& content) {
  std::error_code ec;
  if (fs::exists(path, ec) && read_all(path) == content) return;
  write_text(path.string(), content);
}

void append_little_endian(std::vector<unsigned char>& out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(bits >> (8 * k)));
}

bool newer_than_all(const fs::path& target, const fs::path& dir,
                    const std::vector<std::string>& sources) {
  std::error_code ec;
  const auto t = fs::last_write_time(target, ec);
  if (ec) return false;
  for (const auto& s : sources) {
    const auto ts = fs::last_write_time(dir / s, ec);
    if (ec || ts > t) return false;
  }
  return true;
}

}  // namespace

std::string base64(const unsigned char* data, size_t n) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (size_t i = 0; i < n; i += 3) {
    const uint32_t v = (uint32_t(data[i]) << 16) | (i + 1 < n ? uint32_t(data[i + 1]) << 8 : 0) |
                       (i + 2 < n ? uint32_t(data[i + 2]) : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < n ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < n ? kAlphabet[v & 63] : '=';
  }
  return out;
}

Html write_viewer_assets(const std::string& page_dir) {
  const fs::path dir = fs::path(page_dir) / "viewer";
  for (const ViewerAsset& a : viewer_assets())
    write_if_changed(dir / a.name, std::string(a.content));
  return Html(
      "<link rel=\"stylesheet\" href=\"viewer/viewer.css\">\n"
      "<script src=\"viewer/colour_maps.js\" defer></script>\n"
      "<script src=\"viewer/viewer.js\" defer></script>\n"
      "<script src=\"viewer/report.js\" defer></script>\n");
}

const std::vector<std::string>& reference_viewer_channels() {
  static const std::vector<std::string> c{"AO", "AO_stderr"};
  return c;
}
const std::vector<std::string>& estimate_viewer_channels() {
  static const std::vector<std::string> c{"AO"};
  return c;
}
const std::vector<std::string>& gbuffer_viewer_channels() {
  static const std::vector<std::string> c{"Z", "N.X", "N.Y", "N.Z"};
  return c;
}

std::string write_viewer_data(const std::string& page_dir, const std::vector<std::string>& exrs,
                              const std::vector<std::string>& channels,
                              const std::vector<int>& frame_numbers, double fps) {
  if (exrs.empty()) throw InputError("viewer data: no EXR given");
  if (!frame_numbers.empty() && frame_numbers.size() != exrs.size())
    throw std::invalid_argument("write_viewer_data: one frame number per EXR");
  // One name per EXR path (frame 0): "runs/x/estimates/e.exr" -> "runs__x__estimates__e".
  std::string stem = exrs.front();
  if (stem.ends_with(".exr")) stem.resize(stem.size() - 4);
  const std::string name = file_stem_for(stem), rel = "viewer-data/" + name + ".js";
  const fs::path target = fs::path(page_dir) / rel;
  if (newer_than_all(target, page_dir, exrs)) return rel;
  nlohmann::json record;
  nlohmann::json planes = nlohmann::json::object(), masks = nlohmann::json::array();
  int w = 0, h = 0;
  for (size_t f = 0; f < exrs.size(); ++f) {
    const std::string path = (fs::path(page_dir) / exrs[f]).string();
    const OIIO::ImageBuf image = read_image(path);
    const OIIO::ROI roi = image.roi();
    if (f == 0) {
      w = roi.width();
      h = roi.height();
    } else if (roi.width() != w || roi.height() != h) {
      throw InputError(path + ": " + std::to_string(roi.width()) + "x" +
                       std::to_string(roi.height()) + ", frame 0 is " + std::to_string(w) + "x" +
                       std::to_string(h));
    }
    const size_t n = size_t(w) * size_t(h);
    std::vector<float> pixels(n * roi.nchannels());
    image.get_pixels(roi, OIIO::TypeDesc::FLOAT, pixels.data());
    const int nc = roi.nchannels();
    const int a = channel_index(image, "A", path);
    std::vector<unsigned char> mask(n);
    for (size_t k = 0; k < n; ++k) mask[k] = pixels[k * nc + a] > 0.5f;  // as every reader does
    masks.push_back(base64(mask.data(), n));
    for (const auto& c : channels) {
      const int ci = image.spec().channelindex(c);
      if (ci < 0) continue;
      std::vector<unsigned char> bytes;
      bytes.reserve(4 * n);
      for (size_t k = 0; k < n; ++k) append_little_endian(bytes, pixels[k * nc + ci]);
      planes[c].push_back(base64(bytes.data(), bytes.size()));
    }
  }
  // A channel only some frames have would misalign frames: keep channels every frame has.
  for (auto it = planes.begin(); it != planes.end();)
    it = it->size() == exrs.size() ? std::next(it) : planes.erase(it);
  record["w"] = w;
  record["h"] = h;
  record["frames"] = exrs.size();
  record["channels"] = planes;
  record["mask"] = masks;
  record["source"] = exrs;
  if (!frame_numbers.empty()) record["frame_numbers"] = frame_numbers;
  if (fps > 0.0) record["fps"] = fps;
  write_text(target.string(), "(window.AOEVAL_DATA=window.AOEVAL_DATA||{})[" +
                                  nlohmann::json(name).dump() + "]=" + record.dump() + ";\n");
  return rel;
}

Html viewer_html(const ViewerSpec& spec, const Html& static_html) {
  Html h;
  h << "<div class=\"aoeval-viewer\" data-kind=\"" << attr(spec.kind) << "\" data-a=\""
    << url(spec.a) << "\"";
  if (!spec.b.empty()) h << " data-b=\"" << url(spec.b) << "\"";
  if (spec.kind == "compare") h << " data-labels=\"" << attr(spec.labels) << "\"";
  return h << ">\n<div class=\"av-static\">" << static_html << "</div></div>\n";
}

Html compare_viewer(const std::string& page_dir, const std::string& a_exr, const std::string& b_exr,
                    const std::string& labels, const Html& static_html) {
  ViewerSpec spec;
  spec.a = write_viewer_data(page_dir, {a_exr}, reference_viewer_channels());
  spec.b = write_viewer_data(page_dir, {b_exr}, estimate_viewer_channels());
  spec.labels = labels;
  return viewer_html(spec, static_html);
}

}  // namespace aoeval
