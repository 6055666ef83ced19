// Error maps: figures a researcher reads at a glance. |est - ref| through inferno, est - ref
// through a diverging ColorBrewer RdBu map, grey AO panels, and the labelled four-panel mosaic
// (reference | estimate | |error| | signed error) with a caption. Built from OpenImageIO
// (ImageBufAlgo::color_map, fill, paste, resize, render_text with DejaVu Sans from Debian's
// fonts-dejavu-core). Every function returns an 8-bit sRGB-encoded RGB ImageBuf; the caller writes
// it (aoeval::write_image, atomic). Layout, for a w x h input: a title strip on top, the w x h
// panel below it at panel_origin(h) (pixel for pixel, no resampling), the colour bar to the
// right of the panel (error maps only), a dark canvas around everything.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace aoeval {

struct MapScale {
  float lo, hi;
};

// Inputs of every function: float AO images, row-major, width*height; mask nonzero = compared
// pixel (an empty mask compares every pixel; any other size than w*h is std::invalid_argument).
// Uncompared pixels are drawn in kUncomparedGrey; compared pixels whose value (or error) is NaN or
// infinite are drawn in kInvalidColour and left out of the scale.
// Throws std::runtime_error naming fonts-dejavu-core when the font file is missing. Text is UTF-8;
// with OIIO 2.4 (broken UTF-8 decoding in render_text) it is drawn in ASCII: U+2212 as '-'.
inline constexpr float kUncomparedGrey = 0.25f;                 // sRGB-encoded value
inline constexpr float kInvalidColour[3] = {0.0f, 1.0f, 0.0f};  // pure green: in neither map
inline constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// |est - ref| through inferno scaled to [0, scale_max]; scale_max <= 0 picks
// nice_ceiling(99th percentile of |error| over compared pixels). Colour bar (0, mid, max) on the
// right, title "|estimate − reference|" on top. `used` receives {0, scale_max}.
OIIO::ImageBuf abs_error_map(int w, int h, const float* ref, const float* est,
                             const std::vector<uint8_t>& mask, float scale_max,
                             MapScale* used = nullptr);
// est - ref through RdBu reversed (blue = estimate lower, near-white = 0, red = estimate higher),
// symmetric [-s, s] with s chosen as above from |error|. Colour bar (-s, 0, +s), title
// "estimate − reference" (or `title` when not empty: the dashboard's "new − baseline").
// `used` receives {-s, s}.
OIIO::ImageBuf signed_error_map(int w, int h, const float* ref, const float* est,
                                const std::vector<uint8_t>& mask, float scale_max,
                                MapScale* used = nullptr, const std::string& title = "");
// AO in [0, 1] (clamped) shown as sRGB-encoded grey (displayed luminance = AO), titled.
OIIO::ImageBuf ao_image(int w, int h, const float* ao, const std::vector<uint8_t>& mask,
                        const std::string& title);
// reference | estimate | |error| | signed error, each titled, scales chosen automatically, and
// `caption` on a line under them. Panels keep their pixel size unless the mosaic would be wider
// than kMaxMosaicWidth; then the panels are resized down (OIIO resize) until it fits.
// The mosaic says what it shows, for readers and for the browser test that holds a page's viewer
// beside it: the string attribute kMosaicAttribute of its spec (a PNG text chunk) holds JSON:
// "p99" (of |error|) and "scale" (nice_ceiling(p99), both maps' s); "panels": {"reference",
// "estimate", "abs", "signed": [x, y, w, h]}; "bars": {"abs", "signed": [x, y, w, h]} (top row
// = the map's high end); "labels": {"abs", "signed": [low, middle, high]} as drawn ('-' for the
// minus sign); "source": [w, h] (the panels' size before any resize).
inline constexpr int kMaxMosaicWidth = 4096;
inline constexpr const char* kMosaicAttribute = "aoeval:mosaic";
OIIO::ImageBuf error_mosaic(int w, int h, const float* ref, const float* est,
                            const std::vector<uint8_t>& mask, const std::string& caption);

// The automatic scale: the smallest of {1, 2, 2.5, 5} x 10^k that is >= x (x <= 0 or not finite
// gives 0.01, so a zero-error image still has a valid bar).
float nice_ceiling(float x);
// 99th percentile of |est - ref| over compared, finite pixels (0 when there are none): the value
// of rank p99_rank(n) among the n sorted |errors|.
float abs_error_p99(int w, int h, const float* ref, const float* est,
                    const std::vector<uint8_t>& mask);
// The percentile rule: nearest rank, ceil(0.99 n) - 1 (0-based) of n > 0 sorted values.
size_t p99_rank(size_t n);

// The two maps as tables for the pages' viewer, which colours the same errors in the browser:
// `n` >= 2 evenly spaced coordinates t = i / (n - 1) through the map the error maps use, as 8-bit
// sRGB. drawing/colour_maps_js.cpp writes them, with the rule above, into the viewer's
// colour_maps.js at build time, so a viewer's colour bar and the mosaic beside it agree.
enum class ErrorMapKind { abs, signed_error };
std::vector<std::array<uint8_t, 3>> colour_table(ErrorMapKind kind, int n);

// Where the top-left pixel of an h-pixel-high panel lies in the outputs of abs_error_map,
// signed_error_map and ao_image; and the text size used for an image h pixels high.
struct PanelOrigin {
  int x, y;
};
PanelOrigin panel_origin(int h);
int text_size_px(int h);

}  // namespace aoeval
