// Tests of the frame change (frame_change.h) and of `aoeval dashboard` naming the frames of a
// sequence point that changed between two runs (issue 46, must-show 3), read from the history's
// frames table.
#include "reports/frame_change.h"

#include <gtest/gtest.h>

#include "reports/dashboard_test_util.h"

namespace aoeval {
namespace {

using testutil::History;
using testutil::slurp;

// `n` frames of rmse_excess `excess`, frames [first, last] at `changed` instead. ref_stderr_rms
// 0.01 over 368 pixels: the noise sigma of one frame's rmse_excess is at most
// 0.01 * (2 / 368)^(1/4) = 0.0027, so a change's 3-sigma limit (independent references) is at
// most 3 * sqrt(2) * 0.0027 = 0.0115; 0.02 -> 0.05 exceeds it, 0.02 -> 0.021 does not.
std::vector<FrameRow> frames(int n, double excess, int first = -1, int last = -1,
                             double changed = 0.0) {
  std::vector<FrameRow> out;
  for (int k = 0; k < n; ++k) {
    FrameRow f;
    f.frame = k;
    f.time_ms = 1.0;
    const double e = k >= first && k <= last ? changed : excess;
    f.metrics = {{"rmse_excess", e}, {"ref_stderr_rms", 0.01}, {"bias", 0.0}, {"pixels", 368}};
    out.push_back(f);
  }
  return out;
}

TEST(FrameChange, NamesTheChangedSpansAndIgnoresNoise) {
  const Thresholds t;
  const auto same = frame_change(frames(48, 0.02), frames(48, 0.02, 0, 47, 0.021), t, false);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->compared, 48);
  EXPECT_EQ(same->changed, 0);
  auto after = frames(48, 0.02, 12, 20, 0.05);
  after[40].metrics["rmse_excess"] = 0.002;  // a lone frame that improved
  const auto f = frame_change(frames(48, 0.02), after, t, false);
  ASSERT_TRUE(f);
  EXPECT_EQ(spans_text(f->spans), "12-20, 40");
  EXPECT_EQ(f->changed, 10);
  EXPECT_EQ(f->largest_frame, 12);  // 0.03 moved, the largest (the first of equals)
  EXPECT_DOUBLE_EQ(f->largest_after, 0.05);
  EXPECT_FALSE(frame_change(frames(1, 0.02), frames(1, 0.05), t, false));  // one frame: none
  EXPECT_FALSE(frame_change({}, frames(5, 0.02), t, false));  // a baseline without frames
}

testutil::FakeRow walk(std::vector<FrameRow> f) {
  testutil::FakeRow row;
  row.estimator = "my-temporal";
  row.more_metrics = {{"seq_frames", 48}, {"steady_rmse_excess", 0.02}};
  row.frames = std::move(f);
  return row;
}

// Must-show 3: two runs of a sequence point whose frames 12-20 got worse: the dashboard names
// them (console and page); a rerun with the same frames names none.
TEST(Dashboard, TwoRunsOfASequencePointNameTheFrameRangeThatChanged) {
  History h("frames");
  h.add_rows("r1", "2024-01-01T00:00:00Z", {walk(frames(48, 0.02))});
  h.add_rows("r2", "2024-01-02T00:00:00Z", {walk(frames(48, 0.02))});
  {
    const Dashboard d = build_dashboard(h.options());
    ASSERT_EQ(d.rows.size(), 1u);
    ASSERT_TRUE(d.rows[0].frames);
    EXPECT_EQ(d.rows[0].frames->changed, 0);
    for (const auto& line : console_lines(d)) EXPECT_EQ(line.rfind("FRAMES", 0), std::string::npos);
    EXPECT_NE(slurp(d.page).find("rmse_excess unchanged on all 48 frames compared"),
              std::string::npos);
  }
  h.add_rows("r3", "2024-01-03T00:00:00Z", {walk(frames(48, 0.02, 12, 20, 0.05))});
  const Dashboard d = build_dashboard(h.options());
  ASSERT_EQ(d.rows.size(), 1u);
  const auto lines = console_lines(d);
  const auto frames_line = std::find_if(
      lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("FRAMES ", 0) == 0; });
  ASSERT_NE(frames_line, lines.end());
  EXPECT_EQ(*frames_line,
            "FRAMES my-temporal - scene bunny view main 24x16: rmse_excess changed on frames 12-20 "
            "(9 of 48 frames; most at frame 12: 0.02 -> 0.05)");
  EXPECT_NE(slurp(d.page).find("rmse_excess changed on frames 12-20"), std::string::npos);
}

// Must-show 5's per-frame report section: the dashboard's time-by-frame chart of a sequence point,
// both runs' frames from the store: one polyline each, a point per frame, the top label the
// largest frame time (frame 30 of the new run: 2.5 ms).
TEST(Dashboard, ASequencePointsFrameTimesAreChartedFromTheStore) {
  History h("frame_chart");
  h.add_rows("r1", "2024-01-01T00:00:00Z", {walk(frames(48, 0.02))});
  auto slower = frames(48, 0.02);
  slower[30].time_ms = 2.5;
  h.add_rows("r2", "2024-01-02T00:00:00Z", {walk(slower)});
  const std::string page = slurp(build_dashboard(h.options()).page);
  const auto chart = page.find("<figure class=\"frame-chart\">");
  ASSERT_NE(chart, std::string::npos);
  const std::string svg = page.substr(chart, page.find("</figure>", chart) - chart);
  for (const char* run : {"class=\"baseline\"", "class=\"new\""}) {
    const auto at = svg.find(run);
    ASSERT_NE(at, std::string::npos) << run;
    const auto points = svg.find("points=\"", at);
    const std::string list = svg.substr(points, svg.find("\"/>", points) - points);
    EXPECT_EQ(std::count(list.begin(), list.end(), ','), 48) << run;
  }
  EXPECT_NE(svg.find("text-anchor=\"end\" font-size=\"10\">2.5</text>"), std::string::npos);
  EXPECT_NE(svg.find("frame 47</text>"), std::string::npos);
  // The new run's frame 30 at x = 56 + 416 * 30 / 47, the top (y = 8); frame 0 of both at 1 ms
  // of 2.5 (y = 62).
  EXPECT_NE(svg.find("321.5,8.0"), std::string::npos) << svg;
  EXPECT_NE(svg.find("56.0,62.0"), std::string::npos) << svg;
}

}  // namespace
}  // namespace aoeval
