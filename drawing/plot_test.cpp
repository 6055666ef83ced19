#include "drawing/plot.h"
#include "base/testing/test_temp_dir.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace aoeval {
namespace {

std::string temp_dir() {
  return aoeval::testutil::test_temp_dir("plot").string();
}

TEST(Plot, DrawsALinePlotWithParetoPointsAsAPng) {
  PlotSpec spec;
  spec.title = "rmse against time";
  spec.x_label = "time (ms)";
  spec.y_label = "rmse";
  spec.log_x = true;
  PlotSeries s;
  s.label = "raytraced";
  s.kind = "scatter";
  s.x = {1, 2, 4, 8};
  s.y = {0.1, 0.05, 0.06, 0.02};
  s.highlight = {true, true, false, true};
  spec.series.push_back(s);
  spec.notes = {"a note"};
  const std::string out = temp_dir() + "/plot.png";
  render_plot(spec, out);
  OIIO::ImageBuf image(out);
  ASSERT_TRUE(image.init_spec(out, 0, 0)) << image.geterror();
  EXPECT_EQ(image.spec().width, 770);  // 7 in x 110 dpi
  EXPECT_EQ(image.spec().height, 495);
  // Not a blank canvas: the axes, points and text put dark pixels on the white background.
  const auto stats = OIIO::ImageBufAlgo::computePixelStats(image);
  EXPECT_LT(stats.min[0], 0.2f);
  EXPECT_GT(stats.max[0], 0.9f);
  // The drawn data is the data given: plot.json (what plot.py reads) holds the series as set.
  std::ifstream in(out + ".plot.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["title"], spec.title);
  EXPECT_EQ(j["log_x"], true);
  ASSERT_EQ(j["series"].size(), 1u);
  EXPECT_EQ(j["series"][0]["x"].get<std::vector<double>>(), s.x);
  EXPECT_EQ(j["series"][0]["y"].get<std::vector<double>>(), s.y);
  EXPECT_EQ(j["series"][0]["highlight"].get<std::vector<bool>>(), s.highlight);
}

// A series' colour reaches the pixels and its data moves them: a red series puts pure-red pixels
// on the canvas (nothing else in a plot is red), and other y values give a different image.
TEST(Plot, TheSeriesIsDrawnInItsColourAtItsData) {
  auto red_pixels = [](const std::string& path) {
    OIIO::ImageBuf image(path);
    EXPECT_TRUE(image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << image.geterror();
    const int w = image.spec().width, h = image.spec().height, nc = image.spec().nchannels;
    std::vector<float> px(static_cast<size_t>(w) * h * nc);
    image.get_pixels(OIIO::ROI::All(), OIIO::TypeFloat, px.data());
    std::vector<size_t> red;
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k)
      if (px[k * nc] > 0.7f && px[k * nc + 1] < 0.3f && px[k * nc + 2] < 0.3f) red.push_back(k);
    return red;
  };
  PlotSpec spec;
  PlotSeries s;
  s.colour = "#ff0000";
  s.x = {0, 1, 2, 3};
  s.y = {0, 1, 0, 1};
  spec.series.push_back(s);
  const std::string a = temp_dir() + "/red_a.png", b = temp_dir() + "/red_b.png";
  render_plot(spec, a);
  spec.series[0].y = {1, 0, 1, 0};
  render_plot(spec, b);
  const std::vector<size_t> ra = red_pixels(a), rb = red_pixels(b);
  EXPECT_GT(ra.size(), 200u);  // a 4-point line across a 770 x 495 canvas
  EXPECT_GT(rb.size(), 200u);
  EXPECT_NE(ra, rb);
  PlotSpec none;
  PlotSeries grey;
  grey.colour = "#808080";
  grey.x = s.x;
  grey.y = s.y;
  none.series.push_back(grey);
  const std::string c = temp_dir() + "/grey.png";
  render_plot(none, c);
  EXPECT_TRUE(red_pixels(c).empty());
}

TEST(Plot, MismatchedSeriesAreRejectedBeforeDrawing) {
  PlotSpec spec;
  PlotSeries s;
  s.x = {1, 2};
  s.y = {1};
  spec.series.push_back(s);
  EXPECT_THROW(render_plot(spec, temp_dir() + "/bad.png"), std::runtime_error);
}

TEST(Plot, FailuresOfThePlotterNameTheReason) {
  PlotSpec spec;
  spec.title = "x";
  setenv("AOEVAL_PLOT_SCRIPT", "/nonexistent/plot.py", 1);
  try {
    render_plot(spec, temp_dir() + "/fail.png");
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("failed"), std::string::npos) << e.what();
  }
  unsetenv("AOEVAL_PLOT_SCRIPT");
  // Its log was a temporary (what a killed run leaves, the next one removes) and is gone.
  for (const auto& entry : std::filesystem::directory_iterator(temp_dir())) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find("fail.png.plot.log"), std::string::npos) << name;
    EXPECT_EQ(name.find(".fail.png.plot.tmp-"), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace aoeval
