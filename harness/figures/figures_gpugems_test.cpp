// gpugems-lights: its checks pass and fail on numbers made to do each (so the verdict can go either
// way), and the figure at --quick scale through the command line writes its plot, CSV and caption.
// gpugems-fig17-3 at --quick scale scores both bakes on each floor tessellation, the variants being
// the corpus scene with only the floor's subdivisions changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "base/testing/cli_test_util.h"
#include "base/testing/png_check.h"
#include "base/testing/test_temp_dir.h"
#include "harness/figures/figure_caption_check.h"
#include "harness/figures/figures_gpugems.h"
#include "scenes/corpus.h"

namespace aoeval::figures {
namespace {

namespace fs = std::filesystem;

size_t passed(const std::vector<Check>& checks) {
  return static_cast<size_t>(
      std::count_if(checks.begin(), checks.end(), [](const Check& c) { return c.passed; }));
}

TEST(GpugemsLights, ChecksPassWhereLatLongIsWorseAndFailWhereItIsNot) {
  LightsNumbers good;
  good.lights = {32, 128, 1024};
  good.uniform_rmse = {0.08, 0.03, 0.01};
  good.latlong_rmse = {0.10, 0.06, 0.05};
  good.uniform_polar = 0.134, good.latlong_polar = 0.33;
  const auto ok = lights_checks(good);
  ASSERT_EQ(ok.size(), 4u);
  EXPECT_EQ(passed(ok), 4u);
  EXPECT_EQ(verdict_of(ok), Verdict::reproduced);

  LightsNumbers bad = good;  // lat-long as good as uniform, no pole excess, no convergence
  bad.latlong_rmse = {0.08, 0.03, 0.01};
  bad.uniform_rmse = {0.05, 0.05, 0.05};
  bad.latlong_polar = 0.14;
  const auto no = lights_checks(bad);
  ASSERT_EQ(no.size(), 4u);
  EXPECT_EQ(passed(no), 0u);
  EXPECT_EQ(verdict_of(no), Verdict::not_reproduced);
  for (const Check& c : no) EXPECT_FALSE(c.measured.empty()) << c.rule;
}

TEST(GpugemsLights, QuickFigureWritesPlotCsvAndVerdict) {
  const fs::path d = testutil::test_temp_dir("figures_gpugems_lights");
  const fs::path out = d / "figs";
  const auto r =
      cli_test::run_aoeval("", "figures gpugems-lights --quick --out " + out.string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  const testutil::PngInfo png = testutil::read_png_info(out / "gpugems-lights.png");
  EXPECT_EQ(png.problem, "");
  EXPECT_GE(png.width, 200u);
  EXPECT_GE(png.height, 150u);
  const std::string csv = cli_test::slurp(out / "gpugems-lights.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "distribution,lights,resolution,width,height,polar_share,rmse,rmse_excess,bias,"
            "frame_ms");
  const std::string caption = cli_test::slurp(out / "gpugems-lights.txt");
  EXPECT_NE(caption.find(figures::captions::expected_verdict_line(caption)), std::string::npos)
      << caption;
  // Geometry alone decides this check (where the light directions lie), so it must pass.
  EXPECT_EQ(figures::captions::check_mark(caption, "lat-long concentrates lights at the poles"),
            "pass")
      << caption;
}

TEST(GpugemsFig17_3, QuickFigureScoresBothEstimatorsOnEachFloorTessellation) {
  const fs::path d = testutil::test_temp_dir("figures_gpugems_fig17_3");
  const fs::path out = d / "figs";
  const auto r =
      cli_test::run_aoeval("", "figures gpugems-fig17-3 --quick --out " + out.string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = cli_test::slurp(out / "gpugems-fig17-3.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "estimator,mode,floor_subdivisions,floor_triangles,rays_or_lights,width,height,rmse,"
            "model_rmse,model_pearson,ground_rmse,ground_shadow,ref_ground_shadow,precompute_ms");
  // --quick: floors 1 and 16 (2 and 512 triangles) for both bakes, and shadowmap-ao per pixel.
  EXPECT_NE(csv.find("vertex-baked,vertex,1,2,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("vertex-baked,vertex,16,512,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("shadowmap-ao,vertex,16,512,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("shadowmap-ao,pixel,"), std::string::npos) << csv;
  // The variants are the corpus scene with only the floor's subdivisions changed.
  const std::string variant = cli_test::slurp(out / "scenes" / "elephant-floor16.json");
  EXPECT_NE(variant.find("\"subdivisions\": 16"), std::string::npos) << variant;
  const std::string caption = cli_test::slurp(out / "gpugems-fig17-3.txt");
  EXPECT_NE(caption.find("shadow contrast against the floor's tessellation"), std::string::npos);
}

}  // namespace
}  // namespace aoeval::figures
