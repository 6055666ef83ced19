// Tests of the error maps: output sizes and layout, the colours of zero / positive / negative
// errors and of uncompared pixels, the nice-number scale, the mosaic being the four standalone
// panels side by side (and shrunk past 4096 px), and text really being drawn. One mosaic of a
// synthetic scene goes to /tmp/aoeval_error_maps_test.png for a person to look at.
#include "drawing/error_maps.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <utility>

#include "base/testing/test_temp_dir.h"
#include "scenes/exr_io.h"

namespace aoeval {
namespace {

using Rgb = std::array<float, 3>;

Rgb pixel(const OIIO::ImageBuf& b, int x, int y) {
  Rgb p{};
  b.getpixel(x, y, p.data(), 3);
  return p;
}

void expect_near(const Rgb& a, const Rgb& b, float tol, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << what << " channel " << c;
}

// A w x h image filled with v, a full mask, and helpers to build cases.
struct Case {
  int w, h;
  std::vector<float> ref, est;
  std::vector<uint8_t> mask;
  Case(int w_, int h_, float v)
      : w(w_), h(h_), ref(size_t(w_) * h_, v), est(size_t(w_) * h_, v), mask(size_t(w_) * h_, 1) {}
  size_t at(int x, int y) const { return size_t(y) * w + x; }
};

// Count of pixels in [x0,x1) x [y0,y1) that differ from the canvas colour of pixel (0, 0).
int non_background(const OIIO::ImageBuf& b, int x0, int x1, int y0, int y1) {
  const Rgb bg = pixel(b, 0, 0);
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Rgb p = pixel(b, x, y);
      if (std::fabs(p[0] - bg[0]) + std::fabs(p[1] - bg[1]) + std::fabs(p[2] - bg[2]) > 0.05f) ++n;
    }
  return n;
}

TEST(ErrorMaps, NiceCeiling) {
  EXPECT_FLOAT_EQ(nice_ceiling(0.0731f), 0.1f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.013f), 0.02f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.24f), 0.25f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.1f), 0.1f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.3f), 0.5f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.6f), 1.0f);
  EXPECT_FLOAT_EQ(nice_ceiling(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(nice_ceiling(2.2f), 2.5f);
  EXPECT_FLOAT_EQ(nice_ceiling(3e-4f), 5e-4f);
  EXPECT_FLOAT_EQ(nice_ceiling(0.0f), 0.01f);  // zero error still gets a usable bar
  EXPECT_FLOAT_EQ(nice_ceiling(NAN), 0.01f);
}

TEST(ErrorMaps, ScaleFromP99OfComparedPixels) {
  Case c(10, 10, 0.5f);
  for (int k = 0; k < 100; ++k) c.est[size_t(k)] = 0.5f + 0.001f * float(k + 1);  // 0.001..0.1
  EXPECT_NEAR(abs_error_p99(c.w, c.h, c.ref.data(), c.est.data(), c.mask), 0.099f, 1e-5f);
  // 400 pixels: the two largest errors (1 %) do not set the scale, nor does an uncompared one.
  Case big(20, 20, 0.5f);
  for (float& v : big.est) v = 0.5f + 0.0731f;
  big.est[7] = 100.0f;
  big.est[8] = -3.0f;
  big.mask[9] = 0;
  big.est[9] = 50.0f;
  MapScale used{};
  abs_error_map(big.w, big.h, big.ref.data(), big.est.data(), big.mask, 0.0f, &used);
  EXPECT_FLOAT_EQ(used.hi, 0.1f);
  EXPECT_FLOAT_EQ(used.lo, 0.0f);

  Case d(8, 8, 0.3f);
  for (float& v : d.est) v = 0.3f + 0.24f;
  abs_error_map(d.w, d.h, d.ref.data(), d.est.data(), d.mask, 0.0f, &used);
  EXPECT_FLOAT_EQ(used.hi, 0.25f);
  for (float& v : d.est) v = 0.3f - 0.013f;  // signed: s from |error|, symmetric
  signed_error_map(d.w, d.h, d.ref.data(), d.est.data(), d.mask, 0.0f, &used);
  EXPECT_FLOAT_EQ(used.hi, 0.02f);
  EXPECT_FLOAT_EQ(used.lo, -0.02f);
  signed_error_map(d.w, d.h, d.ref.data(), d.est.data(), d.mask, 0.3f, &used);  // given scale
  EXPECT_FLOAT_EQ(used.hi, 0.3f);
}

TEST(ErrorMaps, SizesPanelPlusBar) {
  const int w = 64, h = 48;
  Case c(w, h, 0.5f);
  const OIIO::ImageBuf a = abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.1f);
  const OIIO::ImageBuf g = ao_image(w, h, c.ref.data(), c.mask, "ref");
  const PanelOrigin o = panel_origin(h);
  const int fs = text_size_px(h);
  EXPECT_EQ(fs, 11);
  EXPECT_EQ(a.spec().nchannels, 3);
  EXPECT_EQ(a.spec().format, OIIO::TypeDesc::UINT8);
  EXPECT_GE(a.spec().width, o.x + w + 16 + fs);  // panel, bar, labels
  EXPECT_EQ(a.spec().height, g.spec().height);
  EXPECT_GE(a.spec().height, o.y + h);
  EXPECT_GE(g.spec().width, o.x + w);
  EXPECT_LT(g.spec().width, a.spec().width);
  EXPECT_EQ(text_size_px(1080), 36);
  // The bar, right of the panel past one margin: inferno's top colour (yellow) at the top.
  const Rgb top = pixel(a, 2 * o.x + w + 8, o.y);
  EXPECT_GT(top[0], 0.9f);
  EXPECT_GT(top[1], 0.9f);
  EXPECT_LT(top[2], 0.8f);
}

TEST(ErrorMaps, ZeroErrorIsTheMapsZeroColour) {
  const int w = 40, h = 30;
  Case c(w, h, 0.42f);
  const PanelOrigin o = panel_origin(h);
  // Inferno's first colour: matplotlib's (sRGB) table; OIIO's table holds it linearised.
  const Rgb inferno0{0.001462f, 0.000466f, 0.013866f};
  OIIO::ImageBuf zero(OIIO::ImageSpec(1, 1, 1, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::zero(zero);
  Rgb oiio0 = pixel(OIIO::ImageBufAlgo::color_map(zero, 0, "inferno"), 0, 0);
  for (float& v : oiio0) v = OIIO::linear_to_sRGB(v);
  expect_near(oiio0, inferno0, 1e-4f, "OIIO inferno[0] encoded");
  const OIIO::ImageBuf a = abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f);
  const OIIO::ImageBuf s = signed_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      expect_near(pixel(a, o.x + x, o.y + y), inferno0, 0.6f / 255, "abs zero");
      for (float v : pixel(s, o.x + x, o.y + y)) ASSERT_GT(v, 0.95f) << x << "," << y;
    }
}

TEST(ErrorMaps, SignedColoursAndUncomparedGrey) {
  const int w = 16, h = 12;
  Case c(w, h, 0.5f);
  c.est[c.at(3, 4)] = 0.6f;   // estimate brighter: red
  c.est[c.at(5, 4)] = 0.45f;  // estimate darker: blue
  c.est[c.at(7, 4)] = NAN;    // broken estimator: green
  c.mask[c.at(9, 4)] = 0;
  c.est[c.at(9, 4)] = 0.9f;  // error ignored: uncompared
  const PanelOrigin o = panel_origin(h);
  const OIIO::ImageBuf s = signed_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.2f);
  const OIIO::ImageBuf a = abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.2f);
  const OIIO::ImageBuf g = ao_image(w, h, c.est.data(), c.mask, "estimate");
  const Rgb pos = pixel(s, o.x + 3, o.y + 4), neg = pixel(s, o.x + 5, o.y + 4);
  EXPECT_GT(pos[0], pos[2] + 0.2f);
  EXPECT_GT(neg[2], neg[0] + 0.1f);
  const Rgb grey{kUncomparedGrey, kUncomparedGrey, kUncomparedGrey};
  const Rgb green{kInvalidColour[0], kInvalidColour[1], kInvalidColour[2]};
  for (const OIIO::ImageBuf* b : {&s, &a, &g}) {
    expect_near(pixel(*b, o.x + 9, o.y + 4), grey, 1.0f / 255, "uncompared");
    expect_near(pixel(*b, o.x + 7, o.y + 4), green, 1.0f / 255, "non-finite");
  }
  // The abs map is brighter where the error is larger; the grey image shows AO sRGB-encoded.
  EXPECT_GT(pixel(a, o.x + 3, o.y + 4)[0], pixel(a, o.x + 5, o.y + 4)[0]);
  EXPECT_NEAR(pixel(g, o.x, o.y)[0], OIIO::linear_to_sRGB(0.5f), 1.0f / 255);
}

TEST(ErrorMaps, TextIsDrawn) {
  const int w = 64, h = 48;
  Case c(w, h, 0.5f);
  const PanelOrigin o = panel_origin(h);
  const OIIO::ImageBuf g = ao_image(w, h, c.ref.data(), c.mask, "reference");
  EXPECT_GT(non_background(g, 0, g.spec().width, 0, o.y), 30);  // title strip is not blank
  const OIIO::ImageBuf a = abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.1f);
  const int label_x = 2 * o.x + w + 16 + 3;  // right of the bar and its ticks
  EXPECT_GT(non_background(a, label_x, a.spec().width, o.y, a.spec().height), 30);
  const OIIO::ImageBuf m = error_mosaic(w, h, c.ref.data(), c.est.data(), c.mask, "caption here");
  EXPECT_GT(non_background(m, 0, m.spec().width, g.spec().height, m.spec().height), 30);
}

TEST(ErrorMaps, MosaicIsTheFourPanelsSideBySide) {
  const int w = 50, h = 40;
  Case c(w, h, 0.6f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      c.ref[c.at(x, y)] = float(x) / w;
      c.est[c.at(x, y)] = c.ref[c.at(x, y)] + 0.05f * std::sin(float(x + 3 * y));
      c.mask[c.at(x, y)] = (x + y) % 11 != 0;
    }
  const OIIO::ImageBuf m = error_mosaic(w, h, c.ref.data(), c.est.data(), c.mask, "x");
  const OIIO::ImageBuf parts[4] = {
      ao_image(w, h, c.ref.data(), c.mask, "reference"),
      ao_image(w, h, c.est.data(), c.mask, "estimate"),
      abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f),
      signed_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f)};
  EXPECT_GE(m.spec().width, 4 * w);
  int x0 = 0;
  for (const auto& p : parts) {
    const OIIO::ImageBuf cut = OIIO::ImageBufAlgo::cut(
        m, OIIO::ROI(x0, x0 + p.spec().width, 0, p.spec().height, 0, 1, 0, 3));
    const auto cmp = OIIO::ImageBufAlgo::compare(cut, p, 0.0f, 0.0f);
    EXPECT_EQ(cmp.nfail, 0u) << "panel at x " << x0;
    x0 += p.spec().width;
  }
  EXPECT_EQ(m.spec().width, x0);
  EXPECT_GT(m.spec().height, parts[0].spec().height);  // the caption line
}

// The mosaic's aoeval:mosaic text (what the browser test holds a page's viewer against) says
// where each panel and bar lies, the scale and p99 the standalone maps use, and the bars' labels;
// the bars' ends are the colour tables' ends (what the viewer's bars draw).
TEST(ErrorMaps, MosaicSaysWhatItShowsAndWhere) {
  const int w = 50, h = 40;
  Case c(w, h, 0.6f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) c.est[c.at(x, y)] = 0.6f + 0.002f * float(x - y);
  const OIIO::ImageBuf m = error_mosaic(w, h, c.ref.data(), c.est.data(), c.mask, "x");
  const auto d = nlohmann::json::parse(m.spec().get_string_attribute(kMosaicAttribute));
  MapScale used{};
  const OIIO::ImageBuf parts[4] = {
      ao_image(w, h, c.ref.data(), c.mask, "reference"),
      ao_image(w, h, c.est.data(), c.mask, "estimate"),
      abs_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f, &used),
      signed_error_map(w, h, c.ref.data(), c.est.data(), c.mask, 0.0f)};
  EXPECT_EQ(d["scale"].get<float>(), used.hi);
  EXPECT_EQ(d["p99"].get<float>(), abs_error_p99(w, h, c.ref.data(), c.est.data(), c.mask));
  EXPECT_EQ(used.hi, 0.1f);  // |error| up to 0.098: p99 0.088 (rank 1979 of 2000)
  EXPECT_EQ(d["labels"]["abs"], (nlohmann::json{"0", "0.05", "0.1"}));
  EXPECT_EQ(d["labels"]["signed"], (nlohmann::json{"-0.1", "0", "+0.1"}));
  EXPECT_EQ(d["source"], (nlohmann::json{w, h}));
  const PanelOrigin o = panel_origin(h);
  int x0 = 0, k = 0;
  for (const char* name : {"reference", "estimate", "abs", "signed"}) {
    EXPECT_EQ(d["panels"][name], (nlohmann::json{x0 + o.x, o.y, w, h})) << name;
    x0 += parts[k++].spec().width;
  }
  for (const auto& [name, kind] :
       {std::pair{"abs", ErrorMapKind::abs}, std::pair{"signed", ErrorMapKind::signed_error}}) {
    const auto bar = d["bars"][name].get<std::array<int, 4>>();
    const auto table = colour_table(kind, 256);
    const Rgb top = pixel(m, bar[0] + bar[2] / 2, bar[1]);
    const Rgb bottom = pixel(m, bar[0] + bar[2] / 2, bar[1] + bar[3] - 1);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(top[ch] * 255.0f, table[255][ch], 1.0f) << name;
      EXPECT_NEAR(bottom[ch] * 255.0f, table[0][ch], 1.0f) << name;
    }
    EXPECT_GT(bar[0], d["panels"][name][0].get<int>() + w) << name;  // right of its panel
  }
}

TEST(ErrorMaps, WideMosaicIsResizedDown) {
  const int w = 1500, h = 100;
  Case c(w, h, 0.5f);
  c.est[c.at(10, 10)] = 0.7f;
  const OIIO::ImageBuf m = error_mosaic(w, h, c.ref.data(), c.est.data(), c.mask, "wide");
  EXPECT_LE(m.spec().width, kMaxMosaicWidth);
  EXPECT_GT(m.spec().width, kMaxMosaicWidth - 200);
  EXPECT_LT(m.spec().height, 100 + 60);  // aspect kept: the panels shrank too
}

TEST(ErrorMaps, BadInputsAreRejected) {
  Case c(4, 4, 0.5f);
  EXPECT_THROW(abs_error_map(0, 4, c.ref.data(), c.est.data(), c.mask, 0.0f),
               std::invalid_argument);
  EXPECT_THROW(signed_error_map(4, 4, nullptr, c.est.data(), c.mask, 0.0f), std::invalid_argument);
  EXPECT_THROW(ao_image(4, 4, c.ref.data(), std::vector<uint8_t>(3, 1), "t"),
               std::invalid_argument);
  EXPECT_NO_THROW(ao_image(4, 4, c.ref.data(), {}, "empty mask = all compared"));
}

// A synthetic AO scene: a ground plane darkened near two spheres, sky uncompared; the estimate is
// noisy, biased dark at the contact shadows and too bright on one sphere.
TEST(ErrorMaps, WritesAMosaicToLookAt) {
  const int w = 320, h = 240;
  Case c(w, h, 0.0f);
  double se = 0.0;
  long n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t k = c.at(x, y);
      const float u = (x - 0.5f * w) / h, v = (y - 0.35f * h) / h;
      const float d1 = std::hypot(u + 0.3f, v - 0.25f), d2 = std::hypot(u - 0.3f, v - 0.2f);
      const bool s1 = std::hypot(u + 0.3f, v + 0.02f) < 0.22f;
      const bool s2 = std::hypot(u - 0.3f, v + 0.02f) < 0.18f;
      uint32_t hsh = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u;
      hsh = (hsh ^ (hsh >> 13)) * 0x5bd1e995u;
      const float noise = 0.08f * (float((hsh ^ (hsh >> 15)) & 0xffff) / 65535.0f - 0.5f);
      float ao = 0.0f;
      if (s1 || s2) {
        ao = 0.55f + 0.4f * (-v + 0.2f);
      } else if (y > 0.45f * h) {
        ao = 1.0f - 0.7f * std::exp(-8.0f * d1 * d1) - 0.6f * std::exp(-10.0f * d2 * d2);
      } else {
        c.mask[k] = 0;
      }
      c.ref[k] = std::clamp(ao, 0.0f, 1.0f);
      float bias = 0.0f;
      if (s2) bias = 0.06f;
      if (!s1 && !s2 && y > 0.45f * h) bias = -0.05f * std::exp(-30.0f * d1 * d1);
      c.est[k] = std::clamp(c.ref[k] + noise + bias, 0.0f, 1.0f);
      if (c.mask[k]) {
        se += double(c.est[k] - c.ref[k]) * (c.est[k] - c.ref[k]);
        ++n;
      }
    }
  char caption[128];
  std::snprintf(caption, sizeof caption, "synthetic/two_spheres %dx%d  rmse %.4f", w, h,
                std::sqrt(se / double(n)));
  const OIIO::ImageBuf m = error_mosaic(w, h, c.ref.data(), c.est.data(), c.mask, caption);
  const std::string png = (aoeval::testutil::test_temp_dir("error_maps") / "mosaic.png").string();
  write_image(png, m);
  const OIIO::ImageBuf back = read_image(png);
  EXPECT_EQ(back.spec().width, m.spec().width);
}

}  // namespace
}  // namespace aoeval
