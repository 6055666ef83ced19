// A synthetic results history for the dashboard's tests (no estimator runs): runs in a SQLite
// store, rows with chosen metrics and times, and fake estimate EXRs beside them.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "base/testing/test_temp_dir.h"
#include "harness/results/results_store.h"
#include "reports/dashboard.h"
#include "reports/regression_config.h"
#include "scenes/exr_io.h"

namespace aoeval::testutil {

namespace fs = std::filesystem;

constexpr int kW = 24, kH = 16;

// A fake estimate: AO = scale * (base + amplitude * pattern), background (A = 0) in the top-left
// corner.
inline void write_estimate(const fs::path& path, double base, double amplitude,
                           double scale = 1.0) {
  OIIO::ImageSpec spec(kW, kH, 2, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"AO", "A"};
  OIIO::ImageBuf image(spec);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float covered = (x < 4 && y < 4) ? 0.0f : 1.0f;
      const float ao =
          static_cast<float>(scale * (base + amplitude * std::sin(0.5 * x) * std::cos(0.3 * y)));
      const float px[2] = {ao, covered};
      image.setpixel(x, y, px);
    }
  fs::create_directories(path.parent_path());
  write_exr(path.string(), image, {});
}

// One row of a fake run.
struct FakeRow {
  std::string estimator;
  nlohmann::json params = nlohmann::json::object();  // each one named in the run name
  double rmse_excess = 0.05, bias = 0.0, base = 0.5, scale = 1.0;
  double time_ms = 1.0;  // the median; the repetitions scatter 2 % around it
  // Effective parameters left out of the run name (defaults, not set by the suite).
  nlohmann::json defaults = nlohmann::json::object();
  nlohmann::json more_metrics = nlohmann::json::object();  // e.g. the sequence keys
  std::string aoeval_version = "0.1.0";
  std::string estimator_version;  // "" = unknown (a file from before the column)
  std::vector<FrameRow> frames;   // a sequence point's, stored with its row (point_record.h)
};

struct History {
  fs::path dir;
  std::string db;
  explicit History(const std::string& name)
      : dir(aoeval::testutil::test_temp_dir("dashboard_" + name)) {
    db = (dir / "results.sqlite").string();
  }
  std::string add_rows(const std::string& run_id, const std::string& started,
                       const std::vector<FakeRow>& rows, const std::string& command = "run quick",
                       const std::string& commit = "0123456789abcdef0123456789abcdef01234567") {
    SqliteStore store(db);
    RunContext c;
    c.run_id = run_id;
    c.command = command;
    c.git_commit = commit;
    c.started = started;
    c.device = "cpu";
    c.output_dir = (dir / run_id).string();
    store.add_run(c);
    for (const FakeRow& f : rows) {
      ResultRow r;
      r.run_id = run_id;
      r.estimator = f.estimator;
      r.params = f.params;
      r.scene = "bunny";
      r.view = "main";
      r.width = kW;
      r.height = kH;
      r.run_name = f.estimator;
      for (const auto& [k, v] : f.params.items()) r.run_name += "/" + k + ":" + v.dump();
      r.run_name += "/scene:bunny/view:main/24x16";
      for (const auto& [k, v] : f.defaults.items()) r.params[k] = v;
      r.git_commit = commit;
      r.aoeval_version = f.aoeval_version;
      r.estimator_version = f.estimator_version;
      r.device = "cpu";
      r.reference = {{"spp", 64}, {"sampler", "sobol"}, {"seed", 1}};
      r.metrics = {{"rmse_excess", f.rmse_excess},
                   {"ref_stderr_rms", 0.01},
                   {"bias", f.bias},
                   {"pixels", kW * kH - 16}};
      r.metrics.update(f.more_metrics);
      r.time_ms_samples = {f.time_ms, f.time_ms * 1.01, f.time_ms * 0.99, f.time_ms * 1.02,
                           f.time_ms};
      r.time_ms_median = f.time_ms;
      r.estimate_file = "estimates/" + file_stem_for(r.run_name) + ".exr";
      write_estimate(dir / run_id / r.estimate_file, f.base, 0.2, f.scale);
      store.add(PointRecord{.row = r, .frames = f.frames, .images = {}});
    }
    return run_id;
  }
  // One run of command `command`: rows (estimator, rmse_excess, bias, AO base); images kept.
  std::string add_run(const std::string& run_id, const std::string& started,
                      const std::vector<std::tuple<std::string, double, double, double>>& rows,
                      const std::string& command = "run quick") {
    std::vector<FakeRow> fake;
    for (const auto& [estimator, rmse_excess, bias, base] : rows) {
      FakeRow f;
      f.estimator = estimator;
      f.rmse_excess = rmse_excess;
      f.bias = bias;
      f.base = base;
      fake.push_back(f);
    }
    return add_rows(run_id, started, fake, command);
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

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace aoeval::testutil
