// The viewer's data path (reports/viewer.h): the floats a page's viewer reads are the EXR's floats,
// bit for bit; and the leaderboard's marks. The browser test (browser_test/check_viewer.js) checks
// the same floats through element.aoevalProbe in Chromium.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "reports/page_assets.h"
#include "reports/suite_report_leaderboard.h"
#include "reports/viewer.h"
#include "reports/viewer_assets.h"
#include "scenes/exr_io.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<unsigned char> unbase64(const std::string& s) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    acc = (acc << 6) | static_cast<uint32_t>(alphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>(acc >> bits));
    }
  }
  return out;
}

TEST(Viewer, Base64MatchesRfc4648) {
  auto b = [](const char* s) {
    return base64(reinterpret_cast<const unsigned char*>(s), strlen(s));
  };
  EXPECT_EQ(b(""), "");
  EXPECT_EQ(b("f"), "Zg==");
  EXPECT_EQ(b("fo"), "Zm8=");
  EXPECT_EQ(b("foo"), "Zm9v");
  EXPECT_EQ(b("foobar"), "Zm9vYmFy");
}

TEST(Viewer, AssetsAreBuiltIn) {
  std::set<std::string> names;
  for (const auto& a : viewer_assets()) {
    names.insert(std::string(a.name));
    EXPECT_GT(a.content.size(), 500u) << a.name;
  }
  EXPECT_EQ(names,
            (std::set<std::string>{"viewer.js", "report.js", "viewer.css", "colour_maps.js"}));
  const fs::path dir = testutil::test_temp_dir("viewer");
  const std::string head = write_viewer_assets(dir.string()).str();
  EXPECT_NE(head.find("viewer/viewer.js"), std::string::npos);
  for (const auto& a : viewer_assets()) EXPECT_EQ(read_file(dir / "viewer" / a.name), a.content);
}

// The pages' stylesheets and the dashboard's script are real files (reports/pages/), built in and
// written beside the page that links them; a name not built in is a programming error.
TEST(Viewer, PageStylesAreBuiltInFiles) {
  std::set<std::string> names;
  for (const auto& a : page_assets()) names.insert(std::string(a.name));
  EXPECT_EQ(names, (std::set<std::string>{"suite.css", "dashboard.css", "gallery.css",
                                          "figures.css", "dashboard.js"}));
  const fs::path dir = testutil::test_temp_dir("page_assets");
  EXPECT_EQ(page_stylesheet(dir.string(), "suite.css").str(),
            "<link rel=\"stylesheet\" href=\"suite.css\">\n");
  const std::string css = read_file(dir / "suite.css");
  EXPECT_NE(css.find("img.mosaic"), std::string::npos) << css;
  EXPECT_THROW(page_stylesheet(dir.string(), "none.css"), std::logic_error);
}

// A 5x3 reference with awkward floats (denormal, negative zero, NaN, 1/3) survives exactly
// (`--viewer-exact`).
TEST(Viewer, DataScriptsHoldTheExrFloatsExactly) {
  const fs::path dir = testutil::test_temp_dir("viewer");
  const int w = 5, h = 3;
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr", "A"};
  OIIO::ImageBuf image(spec);
  std::vector<float> ao(w * h), sd(w * h);
  for (int k = 0; k < w * h; ++k) {
    ao[k] = 1.0f / 3.0f + static_cast<float>(k) * 1e-7f;
    sd[k] = static_cast<float>(k) * 0.001f;
  }
  ao[1] = 1e-40f;  // denormal
  ao[2] = -0.0f;
  ao[3] = std::nanf("");
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int k = y * w + x;
      const float px[3] = {ao[k], sd[k], x == 4 ? 0.0f : 1.0f};
      image.setpixel(x, y, px);
    }
  write_exr((dir / "ref.exr").string(), image, {});
  const auto exact = [&](const std::vector<std::string>& exrs,
                         const std::vector<std::string>& channels) {
    return write_viewer_data(dir.string(), exrs, channels, {}, 0.0, ViewerData::exact);
  };
  const std::string rel = exact({"ref.exr"}, reference_viewer_channels());
  EXPECT_EQ(rel, "viewer-data/" + file_stem_for("ref") + ".js");
  const std::string js = read_file(dir / rel);
  const std::string prefix =
      "// aoeval viewer data: exact float32\n(window.AOEVAL_DATA=window.AOEVAL_DATA||{})[\"" +
      file_stem_for("ref") + "\"]=";
  ASSERT_EQ(js.substr(0, prefix.size()), prefix);
  const auto record =
      nlohmann::json::parse(js.substr(prefix.size(), js.size() - prefix.size() - 2));
  EXPECT_EQ(record["w"], w);
  EXPECT_EQ(record["h"], h);
  EXPECT_EQ(record["frames"], 1);
  for (const auto& [name, want] : {std::pair{"AO", ao}, std::pair{"AO_stderr", sd}}) {
    const auto bytes = unbase64(record["channels"][name][0].get<std::string>());
    ASSERT_EQ(bytes.size(), 4u * w * h) << name;
    for (int k = 0; k < w * h; ++k) {
      uint32_t bits = 0, want_bits;
      for (int b = 0; b < 4; ++b) bits |= uint32_t(bytes[4 * k + b]) << (8 * b);  // little-endian
      std::memcpy(&want_bits, &want[k], 4);
      EXPECT_EQ(bits, want_bits) << name << " pixel " << k;
    }
  }
  const auto mask = unbase64(record["mask"][0].get<std::string>());
  ASSERT_EQ(mask.size(), size_t(w * h));
  for (int k = 0; k < w * h; ++k) EXPECT_EQ(mask[k], k % w == 4 ? 0 : 1) << k;
  // Up to date: not rewritten (a marker after the header survives); a newer EXR rewrites it, and
  // so does a page asking for the other encoding.
  const std::string header = "// aoeval viewer data: exact float32\n";
  std::ofstream(dir / rel) << header << "marker";
  exact({"ref.exr"}, reference_viewer_channels());
  EXPECT_EQ(read_file(dir / rel), header + "marker");
  fs::last_write_time(dir / "ref.exr", fs::last_write_time(dir / rel) + std::chrono::seconds(2));
  exact({"ref.exr"}, reference_viewer_channels());
  EXPECT_EQ(read_file(dir / rel).substr(0, prefix.size()), prefix);
  write_viewer_data(dir.string(), {"ref.exr"}, reference_viewer_channels());
  EXPECT_EQ(read_file(dir / rel).substr(0, 34), "// aoeval viewer data: compact 3\n(");
  // Two frames of different sizes, and a file without coverage, are input errors.
  OIIO::ImageSpec small(2, 2, 2, OIIO::TypeDesc::FLOAT);
  small.channelnames = {"AO", "A"};
  write_exr((dir / "small.exr").string(), OIIO::ImageBuf(small), {});
  EXPECT_THROW(exact({"ref.exr", "small.exr"}, {"AO"}), InputError);
  OIIO::ImageSpec no_a(2, 2, 1, OIIO::TypeDesc::FLOAT);
  no_a.channelnames = {"AO"};
  write_exr((dir / "no_a.exr").string(), OIIO::ImageBuf(no_a), {});
  EXPECT_THROW(exact({"no_a.exr"}, {"AO"}), InputError);
  // The element: the static image inside, the scripts named.
  ViewerSpec v;
  v.a = "viewer-data/ref.js";
  v.b = "viewer-data/est.js";
  const std::string html = viewer_html(v, Html("<img src=\"m.png\">")).str();
  EXPECT_NE(html.find("class=\"aoeval-viewer\""), std::string::npos);
  EXPECT_NE(html.find("data-b=\"viewer-data/est.js\""), std::string::npos);
  EXPECT_NE(html.find("<div class=\"av-static\"><img src=\"m.png\"></div>"), std::string::npos);
  // For a pair of EXRs in one call (the dashboard's new and baseline): both scripts, the labels.
  const std::string pair =
      compare_viewer(dir.string(), "ref.exr", "ref.exr", "baseline,new", Html()).str();
  const std::string ref_js = "viewer-data/" + file_stem_for("ref") + ".js";
  EXPECT_NE(pair.find("data-a=\"" + ref_js + "\" data-b=\"" + ref_js + "\""), std::string::npos)
      << pair;
  EXPECT_NE(pair.find("data-labels=\"baseline,new\""), std::string::npos);
}

// A compact data script: its record (line 2) and its byte string (line 3, js_byte_string
// undone: what charCodeAt(i) & 255 gives the page).
struct CompactScript {
  nlohmann::json record;
  std::string bin;
  std::vector<unsigned char> bytes(const nlohmann::json& at) const {
    const std::string part = bin.substr(at[0].get<size_t>(), at[1].get<size_t>());
    return {part.begin(), part.end()};
  }
};
CompactScript read_compact(const std::string& js) {
  CompactScript c;
  const size_t line2 = js.find('\n') + 1, line3 = js.find('\n', line2) + 1;
  const size_t eq = js.find("]=", line2);
  c.record = nlohmann::json::parse(js.substr(eq + 2, line3 - 2 - (eq + 2)));
  const size_t open = js.find(".bin=\"", line3) + 6, close = js.rfind("\";");
  for (size_t i = open; i < close; ++i) {
    if (js[i] != '\\') {
      c.bin += js[i];
      continue;
    }
    const char e = js[++i];
    c.bin += e == 'n' ? '\n' : e == 'r' ? '\r' : e;
  }
  return c;
}

TEST(Viewer, ByteStringsHoldEveryByte) {
  std::string all;
  for (int b = 0; b < 256; ++b) all += static_cast<char>(b);
  const std::string js =
      "// h\nx[\"k\"]={};\nwindow.AOEVAL_DATA[\"k\"].bin=\"" + js_byte_string(all) + "\";\n";
  EXPECT_EQ(read_compact(js).bin, all);
  EXPECT_EQ(js_byte_string(all).size(), 256u + 4u);  // ", \\, LF and CR escaped
  EXPECT_EQ(js_byte_string("a\"b\\\n\r"), "a\\\"b\\\\\\n\\r");
}

// zlib-inflates a compact plane (the page does it with DecompressionStream('deflate')).
std::vector<unsigned char> inflate(const std::vector<unsigned char>& z, size_t size) {
  std::vector<unsigned char> out(size);
  uLongf n = size;
  EXPECT_EQ(uncompress(out.data(), &n, z.data(), static_cast<uLong>(z.size())), Z_OK);
  EXPECT_EQ(n, size);
  return out;
}

// Issue 42: the compact default. A plane within +-2 (AO_stderr, and AO without its NaN) is
// float16, within 1e-3 of the EXR's floats (4.9e-4 at most); a map shown through a colour map
// (lag) is fixed point in steps of 1/4096; a plane with a NaN or a value beyond 2 (depth) stays
// float32, exact; masks are deflated bytes. Planes are byte-shuffled.
TEST(Viewer, CompactDataIsWithinOneThousandthAndSmaller) {
  const fs::path dir = testutil::test_temp_dir("viewer_compact");
  const int w = 64, h = 48, n = w * h;
  OIIO::ImageSpec spec(w, h, 5, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr", "Z", "A", "lag"};
  OIIO::ImageBuf image(spec);
  std::vector<float> ao(n), sd(n), z(n), lag(n);
  for (int k = 0; k < n; ++k) {
    ao[k] = 0.5f + 0.5f * std::sin(0.05f * static_cast<float>(k));
    sd[k] = 1e-6f * static_cast<float>(k);
    z[k] = 3.0f + 0.01f * static_cast<float>(k);
    lag[k] = 0.3f * std::cos(0.01f * static_cast<float>(k));
  }
  ao[7] = 1.9999f;
  ao[8] = -0.0f;
  for (int k = 0; k < n; ++k) {
    const float px[5] = {ao[k], sd[k], z[k], k % 3 ? 1.0f : 0.0f, lag[k]};
    image.setpixel(k % w, k / w, px);
  }
  write_exr((dir / "ref.exr").string(), image, {});
  const std::string rel =
      write_viewer_data(dir.string(), {"ref.exr"}, {"AO", "AO_stderr", "Z", "lag"});
  const std::string js = read_file(dir / rel);
  const CompactScript script = read_compact(js);
  const nlohmann::json& record = script.record;
  EXPECT_EQ(record["encoding"], "shuffled-deflate");
  EXPECT_EQ(record["kinds"]["AO"][0], "h");
  EXPECT_EQ(record["kinds"]["AO_stderr"][0], "h");
  EXPECT_EQ(record["kinds"]["lag"][0], "q");
  EXPECT_EQ(record["kinds"]["Z"][0], "f");
  for (const auto& [name, want] :
       {std::pair{"AO", ao}, std::pair{"AO_stderr", sd}, std::pair{"lag", lag}}) {
    const auto u = inflate(script.bytes(record["channels"][name][0]), 2u * n);
    const bool fixed = std::string(name) == "lag";
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
      const auto bits = static_cast<uint16_t>(u[k] | u[n + k] << 8);
      const double got = fixed ? static_cast<int16_t>(bits) / double(kViewerFixedScale)
                               : double(half_to_float(bits));
      worst = std::max(worst, std::fabs(got - want[k]));
    }
    EXPECT_LE(worst, fixed ? 0.5 / kViewerFixedScale + 1e-9 : 4.9e-4) << name;
  }
  const auto zu = inflate(script.bytes(record["channels"]["Z"][0]), 4u * n);
  for (int k = 0; k < n; ++k) {
    uint32_t bits = 0, want_bits;
    for (int b = 0; b < 4; ++b) bits |= uint32_t(zu[b * n + k]) << (8 * b);
    std::memcpy(&want_bits, &z[k], 4);
    ASSERT_EQ(bits, want_bits) << "Z pixel " << k;
  }
  const auto mask = inflate(script.bytes(record["mask"][0]), n);
  for (int k = 0; k < n; ++k) ASSERT_EQ(mask[k], k % 3 ? 1 : 0) << k;
  // Smaller than the exact form.
  const fs::path exact_dir = testutil::test_temp_dir("viewer_exact");
  fs::copy_file(dir / "ref.exr", exact_dir / "ref.exr");
  write_viewer_data(exact_dir.string(), {"ref.exr"}, {"AO", "AO_stderr", "Z", "lag"}, {}, 0.0,
                    ViewerData::exact);
  EXPECT_LT(2 * js.size(), read_file(exact_dir / rel).size());
}

// Three frames, the second a copy of the first (a static camera's reference): its planes and mask
// are the first frame's index, the third frame (changed) its own bytes again.
TEST(Viewer, CompactDataStoresARepeatedFrameOnce) {
  const fs::path dir = testutil::test_temp_dir("viewer_repeat");
  const int w = 32, h = 16;
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "AO_stderr", "A"};
  for (int f = 0; f < 3; ++f) {
    OIIO::ImageBuf image(spec);
    for (int k = 0; k < w * h; ++k) {
      const float px[3] = {0.25f + 0.001f * static_cast<float>(k % 97) + (f == 2 ? 0.1f : 0.0f),
                           0.01f * static_cast<float>(k % 7) + (f == 2 ? 0.002f : 0.0f),
                           k % 5 || f < 2 ? 1.0f : 0.0f};
      image.setpixel(k % w, k / w, px);
    }
    write_exr((dir / ("f" + std::to_string(f) + ".exr")).string(), image, {});
  }
  const std::string rel = write_viewer_data(dir.string(), {"f0.exr", "f1.exr", "f2.exr"},
                                            reference_viewer_channels(), {0, 1, 2}, 10.0);
  const auto record = read_compact(read_file(dir / rel)).record;
  for (const std::string name : {"AO", "AO_stderr"}) {
    const auto& planes = record["channels"][name];
    EXPECT_TRUE(planes[0].is_array()) << name;
    EXPECT_EQ(planes[1], 0) << name;
    EXPECT_TRUE(planes[2].is_array()) << name;
  }
  EXPECT_EQ(record["mask"][1], 0);
  EXPECT_TRUE(record["mask"][2].is_array());
}

// float16 conversion: exact for representable values, round to nearest even between them.
TEST(Viewer, HalfFloatsRoundToNearestEven) {
  for (float v : {0.0f, 1.0f, -2.0f, 0.5f, 65504.0f, 6.103515625e-05f, 5.9604645e-08f})
    EXPECT_EQ(half_to_float(float_to_half(v)), v) << v;
  EXPECT_EQ(float_to_half(-0.0f), 0x8000);
  // Halfway between two halves (steps of 1/1024 at 1): to the even one.
  EXPECT_EQ(half_to_float(float_to_half(1.0f + 1.0f / 2048.0f)), 1.0f);
  EXPECT_EQ(half_to_float(float_to_half(1.0f + 3.0f / 2048.0f)), 1.0f + 2.0f / 1024.0f);
  EXPECT_EQ(half_to_float(float_to_half(1.0f + 3.0f / 4096.0f)), 1.0f + 1.0f / 1024.0f);
  for (int k = 0; k <= 20000; ++k) {  // every value in [0, 2]: within half a step
    const float v = 2.0f * static_cast<float>(k) / 20000.0f;
    EXPECT_LE(std::fabs(half_to_float(float_to_half(v)) - v), 4.8829e-4f) << v;
  }
}

// A row whose matched and true scores are the same number (one definition); `true_err` apart.
ResultRow scored(const std::string& estimator, const std::string& scene, double err, double ms,
                 double true_err = -1.0) {
  ResultRow r;
  r.estimator = estimator;
  r.run_name = estimator + "/scene:" + scene + "/view:main/8x8";
  r.scene = scene;
  r.view = "main";
  r.width = r.height = 8;
  r.metrics = {{"rmse_excess", err}};
  r.true_metrics = {{"rmse_excess", true_err < 0.0 ? err : true_err}};
  r.time_ms_median = ms;
  return r;
}

TEST(Leaderboard, MarksTheBestPerSceneAndSkippedRows) {
  std::vector<SuiteReportEntry> entries(4);
  entries[0].row = scored("a", "box", 0.2, 1.0);
  entries[1].row = scored("b", "box", 0.1, 5.0);
  entries[2].row = scored("a", "tree", 0.05, 1.5);
  entries[3].row = scored("b", "tree", 0.0, 0.0);
  entries[3].row.status = "skipped: no device";
  for (auto& e : entries) e.featured = true;
  const std::string html = leaderboard_html(entries, {"box", "tree"}).str();
  EXPECT_NE(html.find("class=\"leaderboard sortable\""), std::string::npos);
  // b is best on box, a on tree (b's skipped row does not count).
  EXPECT_NE(
      html.find("<td class=\"best\" data-v=\"0.1\"><a href=\"#mosaic-b-scene-box-view-main-8x8\""),
      std::string::npos)
      << html;
  EXPECT_NE(html.find("<td class=\"best\" data-v=\"0.05\">"), std::string::npos) << html;
  EXPECT_NE(html.find("<td class=\"skipped\" data-v=\"\"><span title=\"skipped: no device\">"),
            std::string::npos)
      << html;
  EXPECT_EQ(html.find("<td class=\"best\" data-v=\"0.2\""), std::string::npos);
  for (auto& e : entries) e.featured = false;
  EXPECT_TRUE(leaderboard_html(entries, {"box"}).empty());
}

// One truth to rank on: a bounded estimator that is close to its own bounded reference (matched
// 0.034) but far from true AO (0.388) is not starred above one that is close to true AO (0.060);
// its matched score is still shown beside. A sequence point ranks by its steady state.
TEST(Leaderboard, RanksOnTrueAoWithTheMatchedScoreBeside) {
  std::vector<SuiteReportEntry> entries(4);
  entries[0].row = scored("hbao-split-cpu", "box", 0.034, 2.0, 0.388);
  entries[1].row = scored("rtao", "box", 0.059, 9.0, 0.060);
  entries[2].row = scored("gtao", "walk", 0.5, 1.0);
  entries[3].row = scored("rtao", "walk", 0.01, 9.0);
  entries[2].row.metrics.update({{"seq_frames", 24}, {"steady_rmse_excess", 0.03}});
  entries[2].row.true_metrics.update({{"seq_frames", 24}, {"steady_rmse_excess", 0.04}});
  entries[3].row.metrics.update({{"seq_frames", 24}, {"steady_rmse_excess", 0.07}});
  entries[3].row.true_metrics.update({{"seq_frames", 24}, {"steady_rmse_excess", 0.08}});
  for (auto& e : entries) e.featured = true;
  const std::string html = leaderboard_html(entries, {"box", "walk"}).str();
  EXPECT_NE(html.find("<td data-v=\"0.388\"><a href=\"#mosaic-hbao-split-cpu-scene-box"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td data-v=\"0.034\">0.034</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<td class=\"best\" data-v=\"0.06\"><a href=\"#mosaic-rtao-scene-box"),
            std::string::npos)
      << html;
  // The sequence: gtao's steady 0.04 beats rtao's 0.08, though gtao's last frame (0.5) is worse.
  EXPECT_NE(html.find("<td class=\"best\" data-v=\"0.04\"><a href=\"#mosaic-gtao-scene-walk"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td data-v=\"0.08\"><a href=\"#mosaic-rtao-scene-walk"), std::string::npos)
      << html;
  EXPECT_NE(html.find(">true</th><th data-sort=\"2\">matched</th>"), std::string::npos) << html;
  // The rows' order is the true score's (mean rank over the views: rtao 1 and 2, gtao 1 and none,
  // hbao-split-cpu 2 and none), not their order of appearance nor the matched one.
  const auto row = [&](const std::string& label) {
    return html.find("<tr><td class=\"l\">" + label + "</td>");
  };
  ASSERT_NE(row("hbao-split-cpu"), std::string::npos) << html;
  EXPECT_LT(row("rtao"), row("gtao")) << html;
  EXPECT_LT(row("gtao"), row("hbao-split-cpu")) << html;
}

}  // namespace
}  // namespace aoeval
