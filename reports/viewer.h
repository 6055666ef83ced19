// The pages' image viewer (CONTRACT §11) on the C++ side: writes the viewer's own JavaScript and
// CSS (reports/viewer/, built into the binary) beside a page, turns EXR channels into the data
// scripts the viewer loads (viewer.js says why scripts: file:// forbids fetch and canvas reads of
// images), and writes the viewer element around a page's static images. Reads EXRs; runs nothing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "reports/html.h"

namespace aoeval {

// Writes viewer/colour_maps.js, viewer.js, report.js and viewer.css under `page_dir` (atomically,
// only when they differ) and returns the <link>/<script> tags for the page's <head>.
Html write_viewer_assets(const std::string& page_dir);

// The channels a viewer shows: of a reference (AO, AO_stderr), an estimate (AO) and a G-buffer.
// The coverage channel A always comes along as the compared-pixel mask.
const std::vector<std::string>& reference_viewer_channels();
const std::vector<std::string>& estimate_viewer_channels();
const std::vector<std::string>& gbuffer_viewer_channels();

// How the viewer's data holds the EXRs' floats (issue 42: the default suite's float32 data as
// base64 text was 695 MB). compact: each plane byte-shuffled and deflated (zlib), the viewer
// inflating it with the browser's DecompressionStream; a plane whose values all lie within
// +-kViewerHalfRange as float16 (AO, normals: probe values within 4.9e-4 of the EXR's floats,
// 1e-3 promised; relative precision kept, for the exposure control; a kept reference's AO_stderr,
// at 4 significant bits (harness/sweep/kept_references.h), is a float16 whose low mantissa bits
// are zero, and deflates 1.3x smaller than as fixed point), or, for a plane shown only through a
// linear colour map (viewer_fixed_point_channel: flicker, lag), as int16 fixed point in steps of
// 1/kViewerFixedScale (within 1.22e-4; the kept maps.exr holds the same multiples of 1/4096);
// any other plane (depth, a NaN) as float32, exact; a plane or mask that repeats the frame before
// (a static camera's references) as that frame's index. The deflated planes and masks lie one
// after the other in one byte string (js_byte_string), each named by [offset, length]. exact:
// every plane float32, base64 (the EXRs' floats, bit for bit; `--viewer-exact`).
enum class ViewerData { compact, exact };
inline constexpr float kViewerHalfRange = 2.0f;
inline constexpr int kViewerFixedScale = 4096;
bool viewer_fixed_point_channel(const std::string& channel);
// The encoding the page writers use: compact unless the command asked for `--viewer-exact`
// (set once, before any page is written: the pages' writers, deep in reports/, do not each carry
// it).
ViewerData default_viewer_data();
void set_default_viewer_data(ViewerData data);
// Round to nearest even, as IEEE does; half_to_float is exact. For the viewer's data and its test.
uint16_t float_to_half(float f);
float half_to_float(uint16_t h);

// Writes <page_dir>/viewer-data/<name>.js holding `channels` (those the files have) and the
// coverage mask of each frame's EXR (one file per frame; all the same size), encoded as `data`
// says. Rewritten when older than an EXR or written in the other encoding.
// `exrs` are relative to `page_dir`; returns the script's path relative to it. InputError naming
// the file when an EXR is unreadable, lacks A, or differs in size from frame 0. A sequence's
// kept frames give `frame_numbers` (the sequence frame of each EXR: the viewer's slider and
// aoevalProbe's frame argument use them) and `fps` (its play speed).
std::string write_viewer_data(const std::string& page_dir, const std::vector<std::string>& exrs,
                              const std::vector<std::string>& channels,
                              const std::vector<int>& frame_numbers = {}, double fps = 0.0,
                              ViewerData data = default_viewer_data());

// The viewer element around `static_html` (what a page shows without JavaScript). kind "compare":
// `a` the reference's data script, `b` the estimate's, `labels` their names ("reference,
// estimate"; the dashboard's "baseline,new"); kind "gbuffer": `a` alone; kind "maps": `a` alone,
// each of its channels a panel through inferno (a sequence's flicker and lag maps).
struct ViewerSpec {
  std::string kind = "compare";
  std::string a, b;
  std::string labels = "reference,estimate";
};
Html viewer_html(const ViewerSpec& spec, const Html& static_html);

// A sequence's video (CONTRACT §10: the estimate beside the reference's, every kept frame at
// `fps`), which viewer.js draws on a canvas from the viewer's data scripts `spec.a` (reference)
// and `spec.b` (estimate) when it scrolls into view: the frames are not held twice. `manifest`
// names the point's sequence.json (the browser test finds the video by it).
Html video_html(const ViewerSpec& spec, double fps, const std::string& manifest);

// The whole of it for a pair of EXRs (relative to `page_dir`): data scripts, then the element.
// For pages that show an EXR pair as images (the dashboard's new | baseline | difference).
Html compare_viewer(const std::string& page_dir, const std::string& a_exr, const std::string& b_exr,
                    const std::string& labels, const Html& static_html,
                    ViewerData data = default_viewer_data());

// `bytes` as the inside of a JavaScript "..." literal in a script the page loads with charset
// x-user-defined (WHATWG Encoding: byte b < 0x80 is U+00bb, b >= 0x80 is U+F700 + b, so
// charCodeAt(i) & 255 is the byte): each byte as itself but for ", \, LF and CR, escaped. About
// 1.02 bytes per byte, against base64's 1.33 (issue 42: the compact viewer data's planes).
std::string js_byte_string(const std::string& bytes);

// Base64 (RFC 4648, with padding) of `n` bytes.
std::string base64(const unsigned char* data, size_t n);

}  // namespace aoeval
