// Error maps (see error_maps.h). The pixel work is OpenImageIO's: colour maps by
// ImageBufAlgo::color_map (inferno by name, reversed ColorBrewer RdBu by knots), colour-bar ramps
// by the two-colour fill, composition by paste, downsizing by resize, labels by render_text.
// This file only computes errors and scales and decides the layout.
#include "drawing/error_maps.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace aoeval {

namespace {

namespace IBA = OIIO::ImageBufAlgo;
using IBA::TextAlignX;
using IBA::TextAlignY;

constexpr float kCanvas = 0.10f;     // background around panels (sRGB-encoded)
constexpr float kTextGrey = 0.93f;   // titles, labels, caption
constexpr float kTickGrey = 0.70f;   // colour-bar ticks
#define AOEVAL_MINUS "\xE2\x88\x92"  // U+2212 MINUS SIGN, UTF-8
const char* const kAbsTitle = "|estimate " AOEVAL_MINUS " reference|";
const char* const kSignedTitle = "estimate " AOEVAL_MINUS " reference";

// ColorBrewer RdBu, 11 classes, reversed: -s = dark blue, 0 = #f7f7f7, +s = dark red.
constexpr unsigned kRdBuReversed[11] = {0x053061, 0x2166ac, 0x4393c3, 0x92c5de, 0xd1e5f0, 0xf7f7f7,
                                        0xfddbc7, 0xf4a582, 0xd6604d, 0xb2182b, 0x67001f};

// A colour map: OIIO's by name, or RGB knots when name is empty. OIIO's named maps hold
// linearised colours (its inferno starts at 0.000113 where matplotlib's starts at 0.001462), so
// their output is sRGB-encoded afterwards; the RdBu knots are ColorBrewer's sRGB values and are
// interpolated as such, as matplotlib does.
struct ColourMap {
  std::string name;
  std::vector<float> knots;
};

ColourMap inferno_map() {
  return {"inferno", {}};
}

ColourMap diverging_map() {
  ColourMap m;
  for (unsigned hex : kRdBuReversed)
    for (int shift : {16, 8, 0}) m.knots.push_back(static_cast<float>((hex >> shift) & 0xff) / 255);
  return m;
}

// dst: float RGB of t's size; t: one channel of map coordinates in [0, 1].
void apply_map(OIIO::ImageBuf& dst, const OIIO::ImageBuf& t, const ColourMap& m) {
  const bool ok = m.name.empty()
                      ? IBA::color_map(dst, t, 0, static_cast<int>(m.knots.size() / 3), 3, m.knots)
                      : IBA::color_map(dst, t, 0, m.name);
  if (!ok) throw std::runtime_error("error maps: color_map failed: " + dst.geterror());
  if (m.name.empty()) return;
  auto* p = static_cast<float*>(dst.localpixels());
  const size_t n = dst.spec().image_pixels() * 3;
  for (size_t k = 0; k < n; ++k) p[k] = OIIO::linear_to_sRGB(p[k]);
}

// Every size in the figure follows the text size, which follows the image height.
struct Layout {
  int fs, margin, title_h, area_h, bottom, bar_w, tick, caption_h;
};

Layout layout_for(int h) {
  Layout l{};
  l.fs = text_size_px(h);
  l.margin = std::max(4, l.fs / 2);
  l.title_h = static_cast<int>(std::lround(l.fs * 1.9));
  l.area_h = std::max(h, 3 * l.fs);  // room for three bar labels under a tiny panel
  l.bottom = std::max(l.margin, (3 * l.fs + 3) / 4);
  l.bar_w = std::max(16, l.fs);
  l.tick = std::max(3, l.fs / 3);
  l.caption_h = static_cast<int>(std::lround(l.fs * 1.9));
  return l;
}

void require_font() {
  if (!std::filesystem::exists(kFontPath))
    throw std::runtime_error(std::string("error maps: font ") + kFontPath +
                             " is missing; it is provided by the Debian package fonts-dejavu-core"
                             " (apt-get install -y fonts-dejavu-core)");
}

// OIIO 2.4's render_text decodes UTF-8 wrongly (Strutil::utf8_to_unicode; OIIO issue #3933,
// fixed in 2.5): U+2212 comes out as a missing-glyph box. When the linked OIIO has that bug, text
// is drawn in ASCII: minus signs and dashes as '-', U+00D7 as 'x', anything else as '?'.
bool oiio_decodes_utf8() {
  static const bool ok = [] {
    std::vector<uint32_t> cps;
    OIIO::Strutil::utf8_to_unicode("\xC3\xA9" AOEVAL_MINUS, cps);
    return cps == std::vector<uint32_t>{0xE9, 0x2212};
  }();
  return ok;
}

std::string drawable(const std::string& s) {
  if (oiio_decodes_utf8()) return s;
  std::string out;
  for (size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      out += s[i++];
      continue;
    }
    const size_t len = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC0 ? 2 : 1;
    uint32_t cp = len == 1 ? 0 : b & (0x7Fu >> len);
    for (size_t j = 1; j < len && i + j < s.size(); ++j)
      cp = (cp << 6) | (static_cast<unsigned char>(s[i + j]) & 0x3Fu);
    out += (cp == 0x2212 || cp == 0x2013 || cp == 0x2014) ? '-' : cp == 0xD7 ? 'x' : '?';
    i += len;
  }
  return out;
}

int text_width(const std::string& s, int fs) {
  const OIIO::ROI r = IBA::text_size(drawable(s), fs, kFontPath);
  if (!r.defined())
    throw std::runtime_error(std::string("error maps: cannot measure text with ") + kFontPath);
  return r.width();
}

void draw_text(OIIO::ImageBuf& dst, int x, int y, const std::string& s, int fs, TextAlignX ax,
               TextAlignY ay) {
  const float colour[3] = {kTextGrey, kTextGrey, kTextGrey};
  if (!IBA::render_text(dst, x, y, drawable(s), fs, kFontPath, colour, ax, ay))
    throw std::runtime_error("error maps: render_text failed: " + dst.geterror());
}

void check_inputs(int w, int h, const float* a, const float* b, const std::vector<uint8_t>& mask) {
  if (w <= 0 || h <= 0)
    throw std::invalid_argument("error maps: image size " + std::to_string(w) + "x" +
                                std::to_string(h) + " is not positive");
  if (!a || !b) throw std::invalid_argument("error maps: null image pointer");
  if (!mask.empty() && mask.size() != static_cast<size_t>(w) * static_cast<size_t>(h))
    throw std::invalid_argument("error maps: mask has " + std::to_string(mask.size()) +
                                " entries for a " + std::to_string(w) + "x" + std::to_string(h) +
                                " image");
}

enum class Px : uint8_t { kValue, kUncompared, kInvalid };

// Per-pixel est - ref and whether it is drawn from the map, grey or as invalid.
struct Errors {
  std::vector<float> e;
  std::vector<Px> state;
};

Errors errors_of(int w, int h, const float* ref, const float* est,
                 const std::vector<uint8_t>& mask) {
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  Errors r{std::vector<float>(n, 0.0f), std::vector<Px>(n, Px::kValue)};
  for (size_t k = 0; k < n; ++k) {
    if (!mask.empty() && mask[k] == 0) {
      r.state[k] = Px::kUncompared;
      continue;
    }
    r.e[k] = est[k] - ref[k];
    if (!std::isfinite(r.e[k])) r.state[k] = Px::kInvalid;
  }
  return r;
}

float p99_of(const Errors& er) {
  std::vector<float> a;
  for (size_t k = 0; k < er.e.size(); ++k)
    if (er.state[k] == Px::kValue) a.push_back(std::fabs(er.e[k]));
  if (a.empty()) return 0.0f;
  const size_t idx = p99_rank(a.size());
  std::nth_element(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(idx), a.end());
  return a[idx];
}

float chosen_scale(float scale_max, const Errors& er) {
  if (scale_max > 0.0f && std::isfinite(scale_max)) return scale_max;
  return nice_ceiling(p99_of(er));
}

OIIO::ImageBuf float_rgb(int w, int h) {
  return OIIO::ImageBuf(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
}

// Paints uncompared and invalid pixels over a float RGB panel.
void paint_special(OIIO::ImageBuf& rgb, const std::vector<Px>& state) {
  auto* p = static_cast<float*>(rgb.localpixels());
  for (size_t k = 0; k < state.size(); ++k) {
    if (state[k] == Px::kUncompared)
      for (int c = 0; c < 3; ++c) p[k * 3 + c] = kUncomparedGrey;
    else if (state[k] == Px::kInvalid)
      for (int c = 0; c < 3; ++c) p[k * 3 + c] = kInvalidColour[c];
  }
}

// The w x h panel of an error map: t = map coordinate in [0, 1] of each error.
OIIO::ImageBuf error_panel(int w, int h, const Errors& er, float s, bool is_signed) {
  OIIO::ImageBuf t(OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::FLOAT));
  auto* tp = static_cast<float*>(t.localpixels());
  for (size_t k = 0; k < er.e.size(); ++k) {
    const float v = er.state[k] == Px::kValue ? er.e[k] / s : 0.0f;
    tp[k] = std::clamp(is_signed ? 0.5f + 0.5f * v : std::fabs(v), 0.0f, 1.0f);
  }
  OIIO::ImageBuf rgb = float_rgb(w, h);
  apply_map(rgb, t, is_signed ? diverging_map() : inferno_map());
  paint_special(rgb, er.state);
  return rgb;
}

OIIO::ImageBuf grey_panel(int w, int h, const float* ao, const std::vector<uint8_t>& mask) {
  OIIO::ImageBuf rgb = float_rgb(w, h);
  auto* p = static_cast<float*>(rgb.localpixels());
  std::vector<Px> state(static_cast<size_t>(w) * static_cast<size_t>(h), Px::kValue);
  for (size_t k = 0; k < state.size(); ++k) {
    if (!mask.empty() && mask[k] == 0) {
      state[k] = Px::kUncompared;
    } else if (!std::isfinite(ao[k])) {
      state[k] = Px::kInvalid;
    } else {
      const float v = OIIO::linear_to_sRGB(std::clamp(ao[k], 0.0f, 1.0f));
      for (int c = 0; c < 3; ++c) p[k * 3 + c] = v;
    }
  }
  paint_special(rgb, state);
  return rgb;
}

std::string number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

// A colour bar: its map and the labels at its bottom, middle and top.
struct Bar {
  ColourMap map;
  std::string lo, mid, hi;
};

Bar abs_bar(float s) {
  return {inferno_map(), "0", number(s / 2), number(s)};
}
Bar signed_bar(float s) {
  // Appends, not operator+ chains: GCC 12 warns falsely (-Wrestrict, PR 105329) on "+" + string.
  std::string lo(AOEVAL_MINUS), hi("+");
  lo.append(number(s));
  hi.append(number(s));
  return {diverging_map(), lo, "0", hi};
}

int decorated_width(int w, const Layout& l, const std::string& title, const Bar* bar) {
  int right = l.margin;
  if (bar) {
    const int label_w = std::max(
        {text_width(bar->lo, l.fs), text_width(bar->mid, l.fs), text_width(bar->hi, l.fs)});
    right = l.margin + l.bar_w + l.tick + l.fs / 4 + label_w + l.margin;
  }
  return std::max(l.margin + w + right, text_width(title, l.fs) + 2 * l.margin);
}

// Where decorate() put the panel and its colour bar: x, y, width, height in its output.
struct Placed {
  std::array<int, 4> panel{}, bar{};
};

// A panel (float RGB, sRGB-encoded) on the canvas with its title and optional colour bar.
OIIO::ImageBuf decorate(const OIIO::ImageBuf& panel, const std::string& title, const Bar* bar,
                        Placed* placed = nullptr) {
  const int w = panel.spec().width, h = panel.spec().height;
  const Layout l = layout_for(h);
  const int cw = decorated_width(w, l, title, bar), ch = l.title_h + l.area_h + l.bottom;
  OIIO::ImageBuf canvas(OIIO::ImageSpec(cw, ch, 3, OIIO::TypeDesc::UINT8));
  canvas.specmod().attribute("oiio:ColorSpace", "sRGB");
  IBA::fill(canvas, {kCanvas, kCanvas, kCanvas});
  IBA::paste(canvas, l.margin, l.title_h, 0, 0, panel);
  if (placed) placed->panel = {l.margin, l.title_h, w, h};

  // Title centred over the panel, pulled inside the canvas when it is wider than the panel.
  const int tw = text_width(title, l.fs);
  const int cx = std::clamp(l.margin + w / 2, l.margin + tw / 2,
                            std::max(l.margin + tw / 2, cw - l.margin - tw / 2));
  draw_text(canvas, cx, l.title_h / 2, title, l.fs, TextAlignX::Center, TextAlignY::Center);
  if (!bar) return canvas;

  // The bar spans the panel's height: top = high end of the map, bottom = low end.
  const int bx = l.margin + w + l.margin, by = l.title_h, bh = l.area_h;
  if (placed) placed->bar = {bx, by, l.bar_w, bh};
  const OIIO::ImageBuf ramp = IBA::fill({1.0f}, {0.0f}, OIIO::ROI(0, l.bar_w, 0, bh, 0, 1, 0, 1));
  OIIO::ImageBuf ramp_rgb = float_rgb(l.bar_w, bh);
  apply_map(ramp_rgb, ramp, bar->map);
  IBA::paste(canvas, bx, by, 0, 0, ramp_rgb);
  const int ys[3] = {by + bh - 1, by + (bh - 1) / 2, by};
  const std::string* labels[3] = {&bar->lo, &bar->mid, &bar->hi};
  const int tx = bx + l.bar_w;
  for (int i = 0; i < 3; ++i) {
    IBA::fill(canvas, {kTickGrey, kTickGrey, kTickGrey},
              OIIO::ROI(tx, tx + l.tick, ys[i], ys[i] + 1, 0, 1, 0, 3));
    draw_text(canvas, tx + l.tick + l.fs / 4, ys[i], *labels[i], l.fs, TextAlignX::Left,
              TextAlignY::Center);
  }
  return canvas;
}

// The mosaic's kMosaicAttribute (error_maps.h): what it shows and where. Labels in ASCII: a PNG
// text chunk is Latin-1.
std::string mosaic_description(int w, int h, float p99, float s, const Placed (&placed)[4],
                               const Bar (&bars)[2]) {
  const auto ascii = [](const Bar& b) {
    nlohmann::json labels = nlohmann::json::array();
    for (std::string t : {b.lo, b.mid, b.hi}) {
      if (t.rfind(AOEVAL_MINUS, 0) == 0) t.replace(0, 3, "-");
      labels.push_back(t);
    }
    return labels;
  };
  const nlohmann::json d = {{"source", {w, h}},
                            {"p99", p99},
                            {"scale", s},
                            {"panels",
                             {{"reference", placed[0].panel},
                              {"estimate", placed[1].panel},
                              {"abs", placed[2].panel},
                              {"signed", placed[3].panel}}},
                            {"bars", {{"abs", placed[2].bar}, {"signed", placed[3].bar}}},
                            {"labels", {{"abs", ascii(bars[0])}, {"signed", ascii(bars[1])}}}};
  return d.dump();
}

}  // namespace

int text_size_px(int h) {
  return std::max(11, static_cast<int>(std::lround(h / 30.0)));
}

PanelOrigin panel_origin(int h) {
  const Layout l = layout_for(h);
  return {l.margin, l.title_h};
}

float nice_ceiling(float x) {
  if (!(x > 0.0f) || !std::isfinite(x)) return 0.01f;
  const double v = x;
  double p = std::pow(10.0, std::floor(std::log10(v)) - 1.0);
  for (int decade = 0; decade < 3; ++decade, p *= 10.0)
    for (double m : {1.0, 2.0, 2.5, 5.0})
      if (m * p >= v * (1.0 - 1e-6)) return static_cast<float>(m * p);
  return static_cast<float>(p);  // not reached: 10^(k+1) >= v is in the third decade
}

size_t p99_rank(size_t n) {
  if (n == 0) throw std::invalid_argument("p99_rank: no values");
  return static_cast<size_t>(std::ceil(0.99 * static_cast<double>(n))) - 1;
}

std::vector<std::array<uint8_t, 3>> colour_table(ErrorMapKind kind, int n) {
  if (n < 2) throw std::invalid_argument("colour_table: n < 2");
  OIIO::ImageBuf t(OIIO::ImageSpec(n, 1, 1, OIIO::TypeDesc::FLOAT));
  auto* tp = static_cast<float*>(t.localpixels());
  for (int i = 0; i < n; ++i) tp[i] = static_cast<float>(i) / static_cast<float>(n - 1);
  OIIO::ImageBuf rgb = float_rgb(n, 1);
  apply_map(rgb, t, kind == ErrorMapKind::signed_error ? diverging_map() : inferno_map());
  // To bytes as the panels become the 8-bit canvas (OIIO's float -> uint8: round(255 v)).
  OIIO::ImageBuf bytes(OIIO::ImageSpec(n, 1, 3, OIIO::TypeDesc::UINT8));
  if (!bytes.copy_pixels(rgb))
    throw std::runtime_error("colour_table: conversion failed: " + bytes.geterror());
  const auto* b = static_cast<const uint8_t*>(bytes.localpixels());
  std::vector<std::array<uint8_t, 3>> out(static_cast<size_t>(n));
  for (size_t i = 0; i < out.size(); ++i) out[i] = {b[i * 3], b[i * 3 + 1], b[i * 3 + 2]};
  return out;
}

float abs_error_p99(int w, int h, const float* ref, const float* est,
                    const std::vector<uint8_t>& mask) {
  check_inputs(w, h, ref, est, mask);
  return p99_of(errors_of(w, h, ref, est, mask));
}

OIIO::ImageBuf abs_error_map(int w, int h, const float* ref, const float* est,
                             const std::vector<uint8_t>& mask, float scale_max, MapScale* used) {
  require_font();
  check_inputs(w, h, ref, est, mask);
  const Errors er = errors_of(w, h, ref, est, mask);
  const float s = chosen_scale(scale_max, er);
  if (used) *used = {0.0f, s};
  const Bar bar = abs_bar(s);
  return decorate(error_panel(w, h, er, s, false), kAbsTitle, &bar);
}

OIIO::ImageBuf signed_error_map(int w, int h, const float* ref, const float* est,
                                const std::vector<uint8_t>& mask, float scale_max, MapScale* used,
                                const std::string& title) {
  require_font();
  check_inputs(w, h, ref, est, mask);
  const Errors er = errors_of(w, h, ref, est, mask);
  const float s = chosen_scale(scale_max, er);
  if (used) *used = {-s, s};
  const Bar bar = signed_bar(s);
  return decorate(error_panel(w, h, er, s, true), title.empty() ? kSignedTitle : title, &bar);
}

OIIO::ImageBuf ao_image(int w, int h, const float* ao, const std::vector<uint8_t>& mask,
                        const std::string& title) {
  require_font();
  check_inputs(w, h, ao, ao, mask);
  return decorate(grey_panel(w, h, ao, mask), title, nullptr);
}

OIIO::ImageBuf error_mosaic(int w, int h, const float* ref, const float* est,
                            const std::vector<uint8_t>& mask, const std::string& caption) {
  require_font();
  check_inputs(w, h, ref, est, mask);
  const Errors er = errors_of(w, h, ref, est, mask);
  const float p99 = p99_of(er), s = nice_ceiling(p99);
  const Bar bars[2] = {abs_bar(s), signed_bar(s)};
  const std::string titles[4] = {"reference", "estimate", kAbsTitle, kSignedTitle};
  const Bar* bar_of[4] = {nullptr, nullptr, &bars[0], &bars[1]};
  OIIO::ImageBuf panels[4] = {grey_panel(w, h, ref, mask), grey_panel(w, h, est, mask),
                              error_panel(w, h, er, s, false), error_panel(w, h, er, s, true)};

  const auto total_width = [&](int pw, int ph) {
    const Layout l = layout_for(ph);
    int sum = 0;
    for (int i = 0; i < 4; ++i) sum += decorated_width(pw, l, titles[i], bar_of[i]);
    return sum;
  };
  if (total_width(w, h) > kMaxMosaicWidth) {
    // The widest panel width that fits (decorations shrink with the text size, so this holds).
    const auto height_for = [&](int pw) {
      return std::max(1, static_cast<int>(std::lround(static_cast<double>(h) * pw / w)));
    };
    int lo = 1, hi = w;
    while (lo < hi) {
      const int mid = (lo + hi + 1) / 2;
      if (total_width(mid, height_for(mid)) <= kMaxMosaicWidth)
        lo = mid;
      else
        hi = mid - 1;
    }
    const int pw = lo, ph = height_for(lo);
    for (auto& p : panels) {
      // Triangle: no ringing at mask edges, and ~5x faster than the default lanczos3 here.
      p = IBA::resize(p, "triangle", 0.0f, OIIO::ROI(0, pw, 0, ph, 0, 1, 0, 3));
      if (p.has_error()) throw std::runtime_error("error maps: resize: " + p.geterror());
    }
  }

  OIIO::ImageBuf decorated[4];
  Placed placed[4];
  int sum = 0;
  for (int i = 0; i < 4; ++i) {
    decorated[i] = decorate(panels[i], titles[i], bar_of[i], &placed[i]);
    placed[i].panel[0] += sum;
    placed[i].bar[0] += sum;
    sum += decorated[i].spec().width;
  }
  const Layout l = layout_for(panels[0].spec().height);
  const int cap_w = std::min(kMaxMosaicWidth, text_width(caption, l.fs) + 2 * l.margin);
  const int mw = std::max(sum, cap_w), ph = decorated[0].spec().height;
  OIIO::ImageBuf mosaic(OIIO::ImageSpec(mw, ph + l.caption_h, 3, OIIO::TypeDesc::UINT8));
  mosaic.specmod().attribute("oiio:ColorSpace", "sRGB");
  IBA::fill(mosaic, {kCanvas, kCanvas, kCanvas});
  for (int i = 0, x = 0; i < 4; x += decorated[i].spec().width, ++i)
    IBA::paste(mosaic, x, 0, 0, 0, decorated[i]);
  if (!caption.empty())
    draw_text(mosaic, l.margin, ph + l.caption_h / 2, caption, l.fs, TextAlignX::Left,
              TextAlignY::Center);
  mosaic.specmod().attribute(kMosaicAttribute, mosaic_description(w, h, p99, s, placed, bars));
  return mosaic;
}

}  // namespace aoeval

#undef AOEVAL_MINUS
