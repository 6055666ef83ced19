// The dashboard end to end on a synthetic results history (no estimator runs): run selection,
// row pairing, verdicts, failures first, images, charts and the page.
#include "reports/dashboard.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "base/errors.h"
#include "reports/dashboard_test_util.h"
#include "reports/regression_config.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

using testutil::History;
using testutil::kH;
using testutil::kW;
using testutil::slurp;

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
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].find("REGRESSED beta - scene bunny view main 24x16: rmse_excess"), 0u)
      << lines[0];
  // Its estimate also moved (0.6 -> 0.56): a change, reported apart.
  EXPECT_EQ(lines[1].find("CHANGED beta - scene bunny view main 24x16: darker by 0.040 mean AO"),
            0u)
      << lines[1];
  EXPECT_EQ(worse.changed, 1);

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
  EXPECT_EQ(html.find("://"), std::string::npos);  // self-contained: no URL with a scheme

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
  EXPECT_EQ(d.rows.front().params_change, "N (none) -> 8");
  EXPECT_FALSE(d.rows.front().image_note.empty());  // no estimate kept: said, not hidden
  EXPECT_NE(console_lines(d).front().find("parameters changed: N (none) -> 8"), std::string::npos);
}

// A sequence row (CONTRACT §10 keys) of a plug-in whose manifest default alpha moved 0.1 -> 0.41:
// the run name (explicit parameters only) is unchanged, so the rows pair by name.
testutil::FakeRow sequence_row(double alpha, double temporal, double steady) {
  testutil::FakeRow f;
  f.estimator = "my-temporal";
  f.defaults = {{"alpha", alpha}, {"radius", 0.5}};
  f.more_metrics = {{"seq_frames", 16},
                    {"seq_rmse_excess", 0.03},
                    {"steady_rmse_excess", steady},
                    {"temporal_rmse", temporal + 0.001},
                    {"temporal_rmse_excess", temporal},
                    {"converge_frames", 4},
                    {"disocclusion_rmse_excess", 0.06}};
  return f;
}

// Must-show 1: only temporal_rmse_excess worsens, 0.0129 -> 0.0411 (3.2x); the row is
// REGRESSED on that key alone, and the line names the changed default with both values.
TEST(Dashboard, OnlyFlickerWorsenedThreeTimesIsRegressedNamingTheKeyAndTheChangedDefault) {
  History h("flicker");
  h.add_rows("r1", "2024-01-01T00:00:00Z", {sequence_row(0.1, 0.0129, 0.025)});
  h.add_rows("r2", "2024-01-02T00:00:00Z", {sequence_row(0.41, 0.0411, 0.025)});
  const Dashboard d = build_dashboard(h.options());
  EXPECT_EQ(d.regressed, 1);
  EXPECT_EQ(d.improved, 0);
  ASSERT_EQ(d.rows.size(), 1u);
  const RowReport& rep = d.rows.front();
  EXPECT_EQ(rep.verdict, Verdict::regressed);
  EXPECT_EQ(rep.run_name, "my-temporal/scene:bunny/view:main/24x16");
  for (const Check& c : rep.checks)
    EXPECT_EQ(c.verdict == Verdict::regressed, c.figure == "temporal_rmse_excess")
        << c.figure << ": " << c.detail;
  EXPECT_EQ(rep.params_change, "alpha 0.1 -> 0.41");
  ASSERT_EQ(d.by_key.count("temporal_rmse_excess"), 1u);
  EXPECT_EQ(d.by_key.at("temporal_rmse_excess").first, 1);
  const auto lines = console_lines(d);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0],
            "REGRESSED my-temporal alpha=0.41,radius=0.5 scene bunny view main 24x16: "
            "temporal_rmse_excess 0.0129 -> 0.0411 (threshold 0.00129); parameters changed: alpha "
            "0.1 -> 0.41")
      << lines[0];

  // Its threshold in the config, like any other key: a 500 % allowance passes it.
  const fs::path config = h.dir / "loose.json";
  std::ofstream(config) << R"({"defaults": {"temporal_rmse_excess_relative": 5}})";
  DashboardOptions o = h.options();
  o.config_path = config.string();
  EXPECT_EQ(build_dashboard(o).regressed, 0);
  std::ofstream(config) << R"({"defaults": {"temporal_rmse_excess_relatve": 5}})";
  EXPECT_THROW(build_dashboard(o), InputError);
}

// A row whose flicker regressed while its steady error improved is both, says so, and counts in
// both; the aoeval version that changed is named.
TEST(Dashboard, ARowThatRegressedAndImprovedCountsAsBoth) {
  History h("both");
  h.add_rows("r1", "2024-01-01T00:00:00Z", {sequence_row(0.1, 0.0129, 0.025)});
  testutil::FakeRow newer = sequence_row(0.1, 0.0411, 0.012);
  newer.aoeval_version = "0.2.0";
  h.add_rows("r2", "2024-01-02T00:00:00Z", {newer});
  const Dashboard d = build_dashboard(h.options());
  EXPECT_EQ(d.regressed, 1);
  EXPECT_EQ(d.improved, 1);
  EXPECT_EQ(d.both, 1);
  EXPECT_EQ(d.by_key.at("steady_rmse_excess").second, 1);
  const auto lines = console_lines(d);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines[0].find("temporal_rmse_excess 0.0129 -> 0.0411"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("also IMPROVED: steady_rmse_excess 0.025 -> 0.012"), std::string::npos)
      << lines[0];
  EXPECT_NE(lines[0].find("code changed: aoeval 0.1.0 -> 0.2.0"), std::string::npos) << lines[0];
  EXPECT_NE(slurp(d.page).find("1 regressed, 0 warnings, 1 improved (1 of them regressed"),
            std::string::npos);
}

// The estimator's own code changed between the runs (a GLSL plug-in's shader; parameters equal):
// the verdict line and the page name it with both versions. Equal code: no mention.
TEST(Dashboard, AChangedEstimatorCodeIsNamedOnTheVerdictLine) {
  History h("code");
  testutil::FakeRow older = sequence_row(0.1, 0.0129, 0.025);
  older.estimator_version = "glsl:3f2a91c0b1d2";
  testutil::FakeRow same = sequence_row(0.1, 0.0411, 0.025);
  same.estimator_version = older.estimator_version;
  testutil::FakeRow changed = same;
  changed.estimator_version = "glsl:8b0d4e2a7c11";
  h.add_rows("r1", "2024-01-01T00:00:00Z", {older});
  h.add_rows("r2", "2024-01-02T00:00:00Z", {same});
  Dashboard d = build_dashboard(h.options());
  ASSERT_EQ(d.regressed, 1);
  EXPECT_EQ(d.rows.front().code_change, "");
  EXPECT_EQ(console_lines(d)[0].find("code"), std::string::npos) << console_lines(d)[0];

  h.add_rows("r3", "2024-01-03T00:00:00Z", {changed});
  DashboardOptions o = h.options();
  o.baseline_run = "r1";
  d = build_dashboard(o);
  ASSERT_EQ(d.regressed, 1);
  EXPECT_EQ(d.rows.front().params_change, "");
  const std::string line = console_lines(d)[0];
  EXPECT_NE(line.find("; code changed: glsl-plugin:my-temporal 3f2a91c -> 8b0d4e2"),
            std::string::npos)
      << line;
  EXPECT_NE(slurp(d.page).find("code glsl-plugin:my-temporal 3f2a91c -&gt; 8b0d4e2"),
            std::string::npos);

  // A baseline from before the column (no version): unknown, so nothing is claimed.
  testutil::FakeRow unknown = older;
  unknown.estimator_version = "";
  h.add_rows("r4", "2024-01-04T00:00:00Z", {unknown});
  h.add_rows("r5", "2024-01-05T00:00:00Z", {changed});
  EXPECT_EQ(build_dashboard(h.options()).rows.front().code_change, "");
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

// Issue 48: a damaged estimate image is bad input (exit 2 naming the file), never a row that
// passes the change check unseen, and the dashboard writes nothing before it says so.
TEST(Dashboard, DamagedEstimateImageIsAnInputErrorNamingTheFile) {
  const std::vector<std::string> kinds = {"missing", "garbage",  "nan",
                                          "inf",     "negative", "resized"};
  for (const std::string& kind : kinds) {
    History h("damaged_" + kind);
    h.add_run("r1", "2024-01-01T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}});
    h.add_run("r2", "2024-01-02T00:00:00Z", {{"alpha", 0.05, 0.0, 0.5}});
    const fs::path exr =
        h.dir / "r2" / "estimates" / (file_stem_for("alpha/scene:bunny/view:main/24x16") + ".exr");
    ASSERT_TRUE(fs::exists(exr)) << exr;
    if (kind == "missing") {
      fs::remove(exr);
    } else if (kind == "garbage") {
      std::ofstream(exr, std::ios::binary | std::ios::trunc) << "not an EXR";
    } else if (kind == "resized") {
      OIIO::ImageSpec spec(kW + 1, kH, 2, OIIO::TypeDesc::FLOAT);
      spec.channelnames = {"AO", "A"};
      OIIO::ImageBuf image(spec);
      const float px[2] = {0.5f, 1.0f};
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW + 1; ++x) image.setpixel(x, y, px);
      write_exr(exr.string(), image, {});
    } else {
      OIIO::ImageSpec spec(kW, kH, 2, OIIO::TypeDesc::FLOAT);
      spec.channelnames = {"AO", "A"};
      OIIO::ImageBuf image(spec);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const float px[2] = {0.5f, 1.0f};
          image.setpixel(x, y, px);
        }
      const float bad = kind == "nan"   ? std::nanf("")
                        : kind == "inf" ? std::numeric_limits<float>::infinity()
                                        : -0.25f;
      const float px[2] = {bad, 1.0f};
      image.setpixel(9, 7, px);  // a covered pixel
      write_exr(exr.string(), image, {});
    }
    const DashboardOptions o = h.options();
    try {
      build_dashboard(o);
      ADD_FAILURE() << kind << ": accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(exr.string()), std::string::npos) << kind << ": " << what;
      if (kind == "nan" || kind == "inf" || kind == "negative") {
        EXPECT_NE(what.find("pixel (9, 7)"), std::string::npos) << kind << ": " << what;
      }
      if (kind == "resized") {
        EXPECT_NE(what.find("25x16"), std::string::npos) << what;
      }
    }
    EXPECT_FALSE(fs::exists(o.out_dir)) << kind << ": the dashboard wrote before failing";
  }
}

}  // namespace
}  // namespace aoeval
