#include "reports/suite_report.h"
#include "base/testing/test_temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace aoeval {
namespace {

namespace fs = std::filesystem;

ResultRow row(const std::string& estimator, int rays, double rmse_excess, double ms) {
  ResultRow r;
  r.run_id = "run-1";
  r.estimator = estimator;
  r.run_name = estimator + "/rays:" + std::to_string(rays) + "/scene:box/view:main/8x8";
  r.params = {{"rays", rays}};
  r.scene = "box";
  r.view = "main";
  r.width = r.height = 8;
  r.metrics = {{"rmse", rmse_excess + 0.01},
               {"rmse_excess", rmse_excess},
               {"ssim", 0.9},
               {"flip_mean", 0.1},
               {"bias", -0.01}};
  r.true_metrics = r.metrics;
  r.time_ms_median = r.time_ms_min = r.time_ms_max = ms;
  r.repetitions = 3;
  r.pass_ms = {{"horizon_ms", ms / 2}};
  return r;
}

TEST(SuiteReport, PageHasTheSummaryTablesChartsAndSkippedRows) {
  const fs::path out = aoeval::testutil::test_temp_dir("suite_report");
  SuiteReport report;
  report.suite = "tiny";
  report.suite_file = "tiny.json";
  report.context.run_id = "run-1";
  report.context.git_commit = "abc123";
  report.context.machine = "test machine";
  report.wall_s = 12.5;
  // A sweep: the rays:4 point is slower and worse than rays:2, so it is off the front.
  for (auto [rays, err, ms] : {std::tuple{1, 0.2, 1.0}, {2, 0.1, 2.0}, {4, 0.15, 4.0}}) {
    SuiteReportEntry e;
    e.row = row("raytraced", rays, err, ms);
    e.featured = rays == 1;
    e.mosaic_png = e.featured ? "m.png" : "";
    e.row.estimate_file = "e.exr";
    e.reference_exr = "r.exr";
    report.entries.push_back(e);
  }
  SuiteReportEntry skipped;
  skipped.row = row("hbao", 8, 0, 0);
  skipped.row.status = "skipped: no Vulkan device (test)";
  skipped.row.metrics = skipped.row.true_metrics = nlohmann::json::object();
  skipped.featured = true;
  report.entries.push_back(skipped);

  const std::string page = write_suite_report(out.string(), report);
  EXPECT_EQ(page, (out / "index.html").string());
  std::ifstream in(page);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string html = ss.str();
  for (const char* expected : {"id=\"summary\"", "abc123", "test machine", "12.5 s",
                               "id=\"scene-box\"", "class=\"metrics\"", "class=\"timing\"",
                               "horizon_ms", "<img class=\"mosaic\" src=\"m.png\"",
                               "<img class=\"chart\" src=\"runs/run-1/plots/raytraced_",
                               "skipped: no Vulkan device (test)", "id=\"estimator-hbao\"",
                               "href=\"e.exr\"", "href=\"r.exr\""})
    EXPECT_NE(html.find(expected), std::string::npos) << expected;
  // Every image is loaded lazily, so a suite of hundreds of mosaics opens at the speed of its
  // first screen (README, "The suite report": bytes read by the load event).
  EXPECT_NE(html.find("src=\"m.png\" loading=\"lazy\""), std::string::npos);
  const std::string chart = "runs/run-1/plots/" + file_stem_for("raytraced") + ".png";
  EXPECT_NE(html.find("src=\"" + chart + "\" loading=\"lazy\""), std::string::npos);
  for (size_t at = html.find("<img "); at != std::string::npos; at = html.find("<img ", at + 1))
    EXPECT_NE(html.substr(at, html.find('>', at) - at).find("loading=\"lazy\""), std::string::npos)
        << html.substr(at, 120);
  // Scripts only from the page's own folder (the viewer, the sortable leaderboard).
  EXPECT_NE(html.find("<script src=\"viewer/viewer.js\""), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_NE(html.find("id=\"leaderboard\""), std::string::npos);
  EXPECT_TRUE(fs::exists(out / chart));
  EXPECT_FALSE(fs::exists(out / "runs/run-1/plots" / (file_stem_for("hbao") + ".png")))
      << "nothing of it ran";
  // The sweep table marks rays:1 and rays:2 as the front, rays:4 not.
  const std::string front = "<tr class=\"front\"><td class=\"l\"><a href=\"e.exr\">raytraced/rays:";
  EXPECT_NE(html.find(front + "2/"), std::string::npos);
  EXPECT_EQ(html.find(front + "4/"), std::string::npos);
}

}  // namespace
}  // namespace aoeval
