#include "drawing/plot.h"
#include "scenes/test_temp_dir.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <filesystem>

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
  EXPECT_TRUE(std::filesystem::exists(out + ".plot.json"));
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
}

}  // namespace
}  // namespace aoeval
