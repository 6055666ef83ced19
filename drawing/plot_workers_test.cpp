// The pre-started plot workers: they draw, a frozen or dead one is never waited for, and a plot
// error comes back as an error. Each test points $AOEVAL_PLOT_SCRIPT at a missing file after the
// workers started, so a plot drawn by a process of its own fails: success proves a worker drew.
#include "drawing/plot_workers.h"

#include <signal.h>
#include <sys/wait.h>

#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "base/testing/test_temp_dir.h"
#include "drawing/plot.h"

namespace aoeval {
namespace {

std::string temp_dir() {
  return aoeval::testutil::test_temp_dir("plot_workers").string();
}

PlotSpec small_plot() {
  PlotSpec spec;
  spec.title = "drawn by a worker";
  PlotSeries s;
  s.x = {1, 2, 3};
  s.y = {3, 1, 2};
  spec.series.push_back(s);
  spec.width_in = 2.0, spec.height_in = 1.5, spec.dpi = 50;
  return spec;
}

bool is_image(const std::string& path) {
  OIIO::ImageBuf image(path);
  return image.init_spec(path, 0, 0) && image.spec().width == 100 && image.spec().height == 75;
}

struct WorkersStarted : ::testing::Test {
  void SetUp() override {
    PlotWorkers::instance().start(1);
    ASSERT_EQ(PlotWorkers::instance().pids().size(), 1u);
    setenv("AOEVAL_PLOT_SCRIPT", "/nonexistent/plot.py", 1);
  }
  void TearDown() override {
    unsetenv("AOEVAL_PLOT_SCRIPT");
    PlotWorkers::instance().stop();
  }
};

TEST_F(WorkersStarted, AWorkerDrawsPlotAfterPlot) {
  const pid_t pid = PlotWorkers::instance().pids().front();
  for (int i = 0; i < 3; ++i) {
    std::string out = temp_dir();  // appended piecewise: GCC 12's -Wrestrict misfires on a + chain
    out += "/w";
    out += std::to_string(i);
    out += ".png";
    render_plot(small_plot(), out);
    EXPECT_TRUE(is_image(out)) << out;
  }
  EXPECT_EQ(PlotWorkers::instance().pids(), std::vector<pid_t>{pid});  // the same worker
}

// While timed frames run the workers are stopped; a plot then must not wait for them.
TEST_F(WorkersStarted, AFrozenWorkerIsNotUsed) {
  PlotWorkers::instance().freeze();
  EXPECT_THROW(render_plot(small_plot(), temp_dir() + "/frozen.png"), std::runtime_error);
  PlotWorkers::instance().thaw();
  render_plot(small_plot(), temp_dir() + "/thawed.png");
  EXPECT_TRUE(is_image(temp_dir() + "/thawed.png"));
}

TEST_F(WorkersStarted, ADeadWorkerFallsBackToAProcessOfItsOwn) {
  const pid_t pid = PlotWorkers::instance().pids().front();
  kill(pid, SIGKILL);
  unsetenv("AOEVAL_PLOT_SCRIPT");  // the fallback process needs the real script
  const std::string out = temp_dir() + "/after_death.png";
  render_plot(small_plot(), out);
  EXPECT_TRUE(is_image(out));
  EXPECT_TRUE(PlotWorkers::instance().pids().empty());  // never handed out again
}

TEST_F(WorkersStarted, APlotErrorIsReportedAndTheWorkerCarriesOn) {
  try {
    render_plot(small_plot(), temp_dir() + "/x.notaformat");
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("notaformat"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("failed"), std::string::npos) << e.what();
  }
  ASSERT_EQ(PlotWorkers::instance().pids().size(), 1u);
  render_plot(small_plot(), temp_dir() + "/after_error.png");
  EXPECT_TRUE(is_image(temp_dir() + "/after_error.png"));
}

}  // namespace
}  // namespace aoeval
