// The dashboard end to end on a synthetic results history (no estimator runs): run selection,
// row pairing, verdicts, failures first, images, charts and the page.
#include "reports/dashboard.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "errors.h"
#include "exr_io.h"
#include "reports/regression_config.h"
#include "scenes/test_temp_dir.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 24, kH = 16;

// A fake estimate: AO = base + amplitude * pattern, background (A = 0) in the top-left corner.
void write_estimate(const fs::path& path, double base, double amplitude) {
  OIIO::ImageSpec spec(kW, kH, 2, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "A"};
  OIIO::ImageBuf image(spec);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float covered = (x < 4 && y < 4) ? 0.0f : 1.0f;
      const float ao = static_cast<float>(base + amplitude * std::sin(0.5 * x) * std::cos(0.3 * y));
      const float px[2] = {ao, covered};
      image.setpixel(x, y, px);
    }
  fs::create_directories(path.parent_path());
  write_exr(path.string(), image, {});
}

struct History {
  fs::path dir;
  std::string db;
  explicit History(const std::string& name)
      : dir(aoeval::testutil::test_temp_dir("dashboard_" + name)) {
    db = (dir / "results.sqlite").string();
  }
  // One run of command `command`: rows (estimator, rmse_excess, bias, AO base); images kept.
  std::string add_run(const std::string& run_id, const std::string& started,
                      const std::vector<std::tuple<std::string, double, double, double>>& rows,
                      const std::string& command = "run quick") {
    SqliteStore store(db);
    RunContext c;
    c.run_id = run_id;
    c.command = command;
    c.git_commit = "0123456789abcdef0123456789abcdef01234567";
    c.started = started;
    c.device = "cpu";
    c.output_dir = (dir / run_id).string();
    store.add_run(c);
    for (const auto& [estimator, rmse_excess, bias, base] : rows) {
      ResultRow r;
      r.run_id = run_id;
      r.estimator = estimator;
      r.scene = "bunny";
      r.view = "main";
      r.width = kW;
      r.height = kH;
      r.run_name = estimator + "/scene:bunny/view:main/24x16";
      r.device = "cpu";
      r.reference = {{"spp", 64}, {"sampler", "sobol"}, {"seed", 1}};
      r.metrics = {{"rmse_excess", rmse_excess},
                   {"ref_stderr_rms", 0.01},
                   {"bias", bias},
                   {"pixels", kW * kH - 16}};
      r.time_ms_samples = {1.0, 1.01, 0.99, 1.02, 1.0};
      r.time_ms_median = 1.0;
      r.estimate_file = "estimates/" + estimator + ".exr";
      write_estimate(dir / run_id / r.estimate_file, base, 0.2);
      store.add(r);
    }
    return run_id;
  }
  DashboardOptions options() const {
    DashboardOptions o;
    o.database = db;
    o.out_dir = (dir / "dashboard").string();
    o.config_path = default_regression_config_path();
    o.charts = false;  // matplotlib costs seconds per call; one test draws them
    return o;
  }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Dashboard, UnchangedRerunPassesAndARegressionComesFirst) {
  History h("regression");
  h.add_run("r1", "2024-01-01T00:00:00Z", {{"alpha", 0.05, 0.01, 0.5}, {"beta", 0.05, 0.01, 0.6}});
  h.add_run("r2", "2024-01-02T00:00:00Z", {{"alpha", 0.05, 0.01, 0.5}, {"beta", 0.05, 0.01, 0.6}});
  const Dashboard same = build_dashboard(h.options());
  EXPECT_EQ(same.regressed, 0);
  EXPECT_EQ(same.unchanged, 2);
  ASSERT_TRUE(same.before_run);
  EXPECT_EQ(same.before_run->run_id, "r1");
  EXPECT_EQ(same.after_run.run_id, "r2");

  // beta made worse: rmse_excess 0.05 -> 0.09, its estimate darker by 0.04.
  h.add_run("r3", "2024-01-03T00:00:00Z", {{"alpha", 0.05, 0.01, 0.5}, {"beta", 0.09, 0.01, 0.56}});
  DashboardOptions with_charts = h.options();
  with_charts.charts = true;
  const Dashboard worse = build_dashboard(with_charts);
  EXPECT_EQ(worse.regressed, 1);
  ASSERT_FALSE(worse.rows.empty());
  EXPECT_EQ(worse.rows.front().estimator, "beta");  // failures first
  EXPECT_EQ(worse.rows.front().verdict, Verdict::regressed);
  EXPECT_EQ(worse.before_run->run_id, "r2");
  const auto lines = console_lines(worse);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("REGRESSED beta scene bunny"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("rmse_excess"), std::string::npos) << lines[0];

  // Images, charts and the page.
  const RowReport& beta = worse.rows.front();
  const fs::path out = h.options().out_dir;
  for (const auto& png : {beta.new_png, beta.baseline_png, beta.diff_png}) {
    ASSERT_FALSE(png.empty()) << beta.image_note;
    EXPECT_TRUE(fs::exists(out / png)) << png;
  }
  ASSERT_EQ(worse.groups.size(), 2u);
  EXPECT_EQ(worse.groups.front().estimator, "beta");
  ASSERT_EQ(worse.groups.front().charts.size(), 2u);  // rmse_excess and time_ms_median
  for (const auto& chart : worse.groups.front().charts) EXPECT_TRUE(fs::exists(out / chart));
  EXPECT_NE(slurp((out / worse.groups.front().charts[0]).string() + ".plot.json").find("new"),
            std::string::npos);
  const std::string html = slurp(worse.page);
  EXPECT_NE(html.find("REGRESSED (1 row): beta on bunny"), std::string::npos);
  EXPECT_NE(html.find("class=\"swap\""), std::string::npos);
  EXPECT_NE(html.find("data-baseline=\"" + beta.baseline_png + "\""), std::string::npos);
  EXPECT_LT(html.find("beta on bunny"), html.find("alpha on bunny"));
  EXPECT_EQ(html.find("http"), std::string::npos);  // self-contained

  // An explicit baseline: r3 against r1 is the same regression.
  DashboardOptions o = h.options();
  o.baseline_run = "r1";
  EXPECT_EQ(build_dashboard(o).regressed, 1);
  // Judging r2 against r1 explicitly: nothing.
  o.new_run = "r2";
  EXPECT_EQ(build_dashboard(o).regressed, 0);
}

TEST(Dashboard, SkippedRowsFailOrWarnAsConfigured) {
  History h("pairing");
  h.add_run("r1", "2024-01-01T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}, {"beta", 0.05, 0.0, 0.5}});
  {
    // The new run: alpha unchanged, beta skipped.
    SqliteStore store(h.db);
    h.add_run("r2", "2024-01-02T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}});
    ResultRow skipped;
    skipped.run_id = "r2";
    skipped.estimator = "beta";
    skipped.scene = "bunny";
    skipped.view = "main";
    skipped.width = kW;
    skipped.height = kH;
    skipped.run_name = "beta/scene:bunny/view:main/24x16";
    skipped.status = "skipped: no Vulkan device";
    store.add(skipped);
  }
  DashboardOptions o = h.options();
  const Dashboard d = build_dashboard(o);
  EXPECT_EQ(d.regressed, 1);
  EXPECT_EQ(d.rows.front().estimator, "beta");
  EXPECT_NE(d.rows.front().checks.front().detail.find("no Vulkan device"), std::string::npos);

  // The same with "missing": "warn".
  const fs::path config = h.dir / "warn.json";
  std::ofstream(config) << R"({"defaults": {"missing": "warn"}})";
  o.config_path = config.string();
  const Dashboard warned = build_dashboard(o);
  EXPECT_EQ(warned.regressed, 0);
  EXPECT_EQ(warned.warnings, 1);
}

TEST(Dashboard, ParameterChangeIsPairedByEstimatorSceneViewResolution) {
  History h("params");
  h.add_run("r1", "2024-01-01T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}});
  {
    SqliteStore store(h.db);
    RunContext c;
    c.run_id = "r2";
    c.command = "run quick";
    c.started = "2024-01-02T00:00:00Z";
    store.add_run(c);
    ResultRow r = store.rows_of_run("r1").front();
    r.run_id = "r2";
    r.run_name = "alpha/N:8/scene:bunny/view:main/24x16";
    r.params = {{"N", 8}};
    r.metrics["rmse_excess"] = 0.2;
    r.estimate_file = "";
    store.add(r);
  }
  const Dashboard d = build_dashboard(h.options());
  ASSERT_EQ(d.rows.size(), 1u);
  EXPECT_EQ(d.rows.front().verdict, Verdict::regressed);
  EXPECT_EQ(d.rows.front().params_change, "N: (none) -> 8");
  EXPECT_FALSE(d.rows.front().image_note.empty());  // no estimate kept: said, not hidden
  EXPECT_NE(console_lines(d).front().find("parameters changed: N: (none) -> 8"), std::string::npos);
}

TEST(Dashboard, FirstRunHasNoBaselineAndBadInputIsAnInputError) {
  History h("first");
  h.add_run("r1", "2024-01-01T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}});
  const Dashboard d = build_dashboard(h.options());
  EXPECT_FALSE(d.before_run);
  EXPECT_EQ(d.regressed, 0);
  EXPECT_EQ(d.not_compared, 1);
  DashboardOptions o = h.options();
  o.baseline_run = "nope";
  EXPECT_THROW(build_dashboard(o), InputError);
  o = h.options();
  o.database = (h.dir / "absent.sqlite").string();
  EXPECT_THROW(build_dashboard(o), InputError);
  EXPECT_FALSE(fs::exists(o.database));  // not created by asking
}

}  // namespace
}  // namespace aoeval
