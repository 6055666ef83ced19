#include "reports/viewer.h"

#include <zlib.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "base/errors.h"
#include "harness/results/result_row.h"
#include "reports/html.h"
#include "reports/page_assets.h"
#include "reports/viewer_assets.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

void append_little_endian(std::vector<unsigned char>& out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(bits >> (8 * k)));
}

// The first line of a data script: which encoding it holds, so that a page written with the
// other one rewrites it.
std::string data_header(ViewerData data) {
  return data == ViewerData::exact ? "// aoeval viewer data: exact float32\n"
                                   : "// aoeval viewer data: compact 3\n";
}

bool starts_with_header(const fs::path& target, const std::string& header) {
  std::ifstream in(target, std::ios::binary);
  std::string first(header.size(), '\0');
  in.read(first.data(), static_cast<std::streamsize>(first.size()));
  return in && first == header;
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

namespace {
std::atomic<ViewerData> g_default_viewer_data{ViewerData::compact};
}  // namespace

ViewerData default_viewer_data() {
  return g_default_viewer_data.load();
}
void set_default_viewer_data(ViewerData data) {
  g_default_viewer_data.store(data);
}

uint16_t float_to_half(float f) {
  uint32_t x;
  std::memcpy(&x, &f, sizeof x);
  const auto sign = static_cast<uint16_t>((x >> 16) & 0x8000u);
  x &= 0x7fffffffu;
  if (x >= 0x47800000u)  // |f| >= 65536 (or inf, NaN): the callers keep such planes in float32
    return static_cast<uint16_t>(sign | (x > 0x7f800000u ? 0x7e00u : 0x7c00u));
  if (x < 0x38800000u) {  // below 2^-14: a subnormal half, |f| / 2^-24 rounded (to even)
    float a;
    std::memcpy(&a, &x, sizeof a);
    return static_cast<uint16_t>(sign | static_cast<uint16_t>(std::nearbyint(a * 16777216.0f)));
  }
  // Normal: rebias the exponent, keep 10 mantissa bits, round to nearest even (a carry out of the
  // mantissa moves to the next exponent, as it should).
  uint32_t h = ((x >> 23) - 127 + 15) << 10 | (x & 0x7fffffu) >> 13;
  const uint32_t rest = x & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;
  return static_cast<uint16_t>(sign | h);
}

float half_to_float(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16, e = (h >> 10) & 0x1fu,
                 m = h & 0x3ffu;
  float v;
  if (e == 0) {
    v = std::ldexp(static_cast<float>(m), -24);
  } else if (e == 31) {
    v = m ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
  } else {
    const uint32_t bits = (e - 15 + 127) << 23 | m << 13;
    std::memcpy(&v, &bits, sizeof v);
  }
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  bits |= sign;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

bool viewer_fixed_point_channel(const std::string& channel) {
  return channel == "flicker" || channel == "lag";
}

// A plane's bytes, shuffled, as `kind` says: 'f' float32, 'h' float16, 'q' int16 of
// value x kViewerFixedScale.
static std::vector<unsigned char> pack_plane(const float* values, size_t n, char kind) {
  const size_t size = kind == 'f' ? 4 : 2;
  std::vector<unsigned char> shuffled(n * size);
  for (size_t k = 0; k < n; ++k) {
    uint32_t bits;
    if (kind == 'h') {
      bits = float_to_half(values[k]);
    } else if (kind == 'q') {
      bits = static_cast<uint16_t>(
          static_cast<int16_t>(std::lrint(values[k] * static_cast<float>(kViewerFixedScale))));
    } else {
      std::memcpy(&bits, &values[k], sizeof bits);
    }
    for (size_t b = 0; b < size; ++b)
      shuffled[b * n + k] = static_cast<unsigned char>(bits >> (8 * b));
  }
  return shuffled;
}

// float16 (or fixed point) only where it holds every value within 1e-3 (see ViewerData); NaN and
// infinities stay float32.
static char plane_kind(const std::string& channel, const float* values, size_t n) {
  for (size_t k = 0; k < n; ++k)
    if (!(std::fabs(values[k]) <= kViewerHalfRange)) return 'f';
  return viewer_fixed_point_channel(channel) ? 'q' : 'h';
}

// Appends `bytes` to `blob`; returns [offset, length], what the record holds in their place.
static nlohmann::json append_blob(std::string& blob, const std::vector<unsigned char>& bytes) {
  const nlohmann::json at = nlohmann::json::array({blob.size(), bytes.size()});
  blob.append(bytes.begin(), bytes.end());
  return at;
}

std::string js_byte_string(const std::string& bytes) {
  std::string out;
  out.reserve(bytes.size() + bytes.size() / 32);
  for (const char c : bytes) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else {
      out += c;
    }
  }
  return out;
}

// zlib level 4 rather than the default 6: the default report's viewer planes (348 MB raw, 2795
// segments) deflate in 2.1 s of CPU instead of 5.5 s, to 43.4 MB instead of 42.4 (levels 1 and 3:
// 1.2 s / 46.2 MB and 1.8 s / 44.7 MB); the report stage waits for all of it.
constexpr int kViewerDeflateLevel = 4;

static std::vector<unsigned char> deflate_bytes(const std::vector<unsigned char>& in) {
  uLongf size = compressBound(static_cast<uLong>(in.size()));
  std::vector<unsigned char> out(size);
  if (compress2(out.data(), &size, in.data(), static_cast<uLong>(in.size()), kViewerDeflateLevel) !=
      Z_OK)
    throw std::runtime_error("viewer data: zlib compress2 failed");
  out.resize(size);
  return out;
}

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
                              const std::vector<int>& frame_numbers, double fps, ViewerData data) {
  if (exrs.empty()) throw InputError("viewer data: no EXR given");
  if (!frame_numbers.empty() && frame_numbers.size() != exrs.size())
    throw std::invalid_argument("write_viewer_data: one frame number per EXR");
  // One name per EXR path (frame 0): "runs/x/estimates/e.exr" -> "runs__x__estimates__e".
  std::string stem = exrs.front();
  if (stem.ends_with(".exr")) stem.resize(stem.size() - 4);
  const std::string name = file_stem_for(stem), rel = "viewer-data/" + name + ".js";
  const fs::path target = fs::path(page_dir) / rel;
  const std::string header = data_header(data);
  if (newer_than_all(target, page_dir, exrs) && starts_with_header(target, header)) return rel;
  const bool compact = data == ViewerData::compact;
  nlohmann::json record;
  nlohmann::json planes = nlohmann::json::object(), masks = nlohmann::json::array();
  nlohmann::json kinds = nlohmann::json::object();  // compact: "h" (float16) or "f" per plane
  int w = 0, h = 0;
  std::map<std::string, std::vector<unsigned char>> last;  // compact: each plane's last bytes
  std::vector<unsigned char> last_mask;
  std::string blob;  // compact: every deflated plane and mask, one after the other
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
    if (compact) {
      // A frame that repeats the one before (a static camera's reference): that frame's index.
      if (f > 0 && mask == last_mask) {
        masks.push_back(masks.back().is_number() ? masks.back() : nlohmann::json(f - 1));
      } else {
        masks.push_back(append_blob(blob, deflate_bytes(mask)));
      }
      last_mask = std::move(mask);
    } else {
      masks.push_back(base64(mask.data(), n));
    }
    for (const auto& c : channels) {
      const int ci = image.spec().channelindex(c);
      if (ci < 0) continue;
      if (compact) {
        std::vector<float> values(n);
        for (size_t k = 0; k < n; ++k) values[k] = pixels[k * nc + ci];
        const char kind = plane_kind(c, values.data(), n);
        std::vector<unsigned char> packed = pack_plane(values.data(), n, kind);
        const std::string kind_name(1, kind);
        if (f > 0 && packed == last[c] && kinds[c].size() == f && kinds[c].back() == kind_name) {
          const nlohmann::json& before = planes[c].back();
          planes[c].push_back(before.is_number() ? before : nlohmann::json(f - 1));
        } else {
          planes[c].push_back(append_blob(blob, deflate_bytes(packed)));
        }
        kinds[c].push_back(kind_name);
        last[c] = std::move(packed);
        continue;
      }
      std::vector<unsigned char> bytes;
      bytes.reserve(4 * n);
      for (size_t k = 0; k < n; ++k) append_little_endian(bytes, pixels[k * nc + ci]);
      planes[c].push_back(base64(bytes.data(), bytes.size()));
    }
  }
  // A channel only some frames have would misalign frames: keep channels every frame has.
  for (auto it = planes.begin(); it != planes.end();) {
    if (it->size() == exrs.size()) {
      ++it;
      continue;
    }
    kinds.erase(it.key());
    it = planes.erase(it);
  }
  if (compact) {
    record["encoding"] = "shuffled-deflate";
    record["kinds"] = kinds;
  }
  record["w"] = w;
  record["h"] = h;
  record["frames"] = exrs.size();
  record["channels"] = planes;
  record["mask"] = masks;
  record["source"] = exrs;
  if (!frame_numbers.empty()) record["frame_numbers"] = frame_numbers;
  if (fps > 0.0) record["fps"] = fps;
  const std::string key = nlohmann::json(name).dump();
  std::string script =
      header + "(window.AOEVAL_DATA=window.AOEVAL_DATA||{})[" + key + "]=" + record.dump() + ";\n";
  if (compact) script += "window.AOEVAL_DATA[" + key + "].bin=\"" + js_byte_string(blob) + "\";\n";
  write_text(target.string(), script);
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

Html video_html(const ViewerSpec& spec, double fps, const std::string& manifest) {
  return Html("<div class=\"aoeval-video\" data-a=\"")
         << url(spec.a) << "\" data-b=\"" << url(spec.b) << "\" data-fps=\"" << number(fps)
         << "\" data-manifest=\"" << url(manifest) << "\"><noscript>The video plays from the "
         << "viewer's data, with JavaScript.</noscript></div>\n";
}

Html compare_viewer(const std::string& page_dir, const std::string& a_exr, const std::string& b_exr,
                    const std::string& labels, const Html& static_html, ViewerData data) {
  ViewerSpec spec;
  spec.a = write_viewer_data(page_dir, {a_exr}, reference_viewer_channels(), {}, 0.0, data);
  spec.b = write_viewer_data(page_dir, {b_exr}, estimate_viewer_channels(), {}, 0.0, data);
  spec.labels = labels;
  return viewer_html(spec, static_html);
}

}  // namespace aoeval
