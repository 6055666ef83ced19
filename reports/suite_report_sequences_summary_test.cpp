// The sequences summary (suite_report_sequences_summary.h) on synthetic points: the table ranks
// each scene view's points on true steady_rmse_excess, not the matched one nor the last frame;
// the overlay puts every point of a view on one chart; the maps figure draws flicker | lag and
// opens them in a "maps" viewer whose data holds both channels.
#include "reports/suite_report_sequences_summary.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "base/testing/test_temp_dir.h"
#include "reports/suite_report_leaderboard.h"
#include "scenes/exr_io.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

ResultRow sequence_row(const std::string& estimator, double last, double steady,
                       double true_steady) {
  ResultRow r;
  r.estimator = estimator;
  r.run_name = estimator + "/scene:dragon/view:walk/8x6";
  r.scene = "dragon";
  r.view = "walk";
  r.width = 8;
  r.height = 6;
  r.metrics = {{"rmse_excess", last}, {"seq_frames", 4}, {"steady_rmse_excess", steady}};
  r.true_metrics = {{"rmse_excess", last},
                    {"seq_frames", 4},
                    {"steady_rmse_excess", true_steady},
                    {"temporal_rmse_excess", 0.01},
                    {"lag_rmse_excess", 0.2}};
  return r;
}

TEST(SequencesSummary, RanksEachViewOnTrueSteadyAndOverlaysItsPoints) {
  // hbao: best matched steady (0.03) and best last frame (0.01), worst true steady (0.39).
  const ResultRow hbao = sequence_row("hbao-split-cpu", 0.01, 0.03, 0.39);
  const ResultRow rtao = sequence_row("rtao", 0.2, 0.06, 0.06);
  const ResultRow gtao = sequence_row("gtao", 0.3, 0.05, 0.05);
  std::vector<SequencePoint> points;
  for (const ResultRow* r : {&hbao, &rtao, &gtao})
    points.push_back({r, {{"true_rmse_excess_by_frame", {0.1, 0.2, 0.3, 0.4}}}, "seq"});
  const std::string html = sequence_summary_table(points).str();
  const auto at = [&](const std::string& name) { return html.find(">" + name + "</a></td>"); };
  ASSERT_NE(at("gtao"), std::string::npos) << html;
  EXPECT_LT(at("gtao"), at("rtao")) << html;
  EXPECT_LT(at("rtao"), at("hbao-split-cpu")) << html;
  EXPECT_NE(html.find("class=\"sortable sequences-summary\""), std::string::npos);
  EXPECT_NE(html.find("<td data-v=\"0.39\">0.39</td><td data-v=\"0.03\">0.03</td>"),
            std::string::npos)
      << html;

  const fs::path dir = testutil::test_temp_dir("sequences_summary");
  std::vector<std::pair<PlotSpec, std::string>> plots;
  const std::string figures = sequence_overlay_charts(dir.string(), "plots", points, plots).str();
  ASSERT_EQ(plots.size(), 1u) << "one chart for the one scene view";
  EXPECT_EQ(plots[0].first.series.size(), 3u);
  EXPECT_EQ(plots[0].first.series[0].label, "gtao");
  EXPECT_EQ(plots[0].first.y_label, "true rmse_excess (against true AO)");
  EXPECT_NE(figures.find("against true AO"), std::string::npos);
  EXPECT_TRUE(sequence_summary_table({}).empty());
}

TEST(SequencesSummary, MapsFigureOpensFlickerAndLagInTheViewer) {
  const fs::path dir = testutil::test_temp_dir("sequences_maps");
  fs::create_directories(dir / "seq");
  OIIO::ImageSpec spec(8, 6, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"flicker", "lag", "A"};
  OIIO::ImageBuf maps(spec);
  std::vector<float> pixels(8 * 6 * 3, 0.0f);
  for (int p = 0; p < 48; ++p) {
    pixels[3 * p] = 0.01f * p;
    pixels[3 * p + 1] = p % 8 < 2 ? 0.3f : 0.0f;  // a trail in the two left columns
    pixels[3 * p + 2] = 1.0f;
  }
  maps.set_pixels(maps.roi(), OIIO::TypeDesc::FLOAT, pixels.data());
  write_exr((dir / "seq" / "maps.exr").string(), maps, {});
  const ResultRow row = sequence_row("gtao", 0.3, 0.05, 0.05);
  const std::string html =
      sequence_maps_figure(dir.string(), {&row, {{"maps", "seq/maps.exr"}}, "seq"}).str();
  EXPECT_NE(html.find("data-kind=\"maps\""), std::string::npos) << html;
  EXPECT_NE(html.find("src=\"seq/maps.png\""), std::string::npos) << html;
  EXPECT_TRUE(fs::exists(dir / "seq" / "maps.png"));
  const OIIO::ImageBuf png = read_image((dir / "seq" / "maps.png").string());
  EXPECT_EQ(png.spec().width, 2 * 8 + 4);
  // The viewer's data holds both maps.
  bool found = false;
  for (const auto& f : fs::directory_iterator(dir / "viewer-data")) {
    std::ifstream in(f.path());
    const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    found = found ||
            (s.find("\"flicker\"") != std::string::npos && s.find("\"lag\"") != std::string::npos);
  }
  EXPECT_TRUE(found);
  // A manifest without maps (an older run, --no-estimates): no figure.
  EXPECT_TRUE(sequence_maps_figure(dir.string(), {&row, nlohmann::json::object(), "seq"}).empty());
}

}  // namespace
}  // namespace aoeval
