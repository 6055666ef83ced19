#include "reports/suite_report_mosaics.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "base/errors.h"
#include "drawing/error_maps.h"
#include "reports/suite_report.h"
#include "reports/suite_report_charts.h"
#include "reports/suite_report_leaderboard.h"
#include "scenes/ao_exr.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

double chart_error(const ResultRow& r) {
  return true_score(r);  // what the charts plot (kChartMetric)
}

// Marks the entries on their (estimator, scene view) series' Pareto front, as the charts do.
void feature_fronts(SuiteReport& r) {
  std::map<std::string, std::vector<size_t>> series;
  for (size_t i = 0; i < r.entries.size(); ++i) {
    const ResultRow& row = r.entries[i].row;
    if (row.status != "ok") continue;
    series[row.estimator + "|" + row.scene + "/" + row.view + " " + std::to_string(row.width) +
           "x" + std::to_string(row.height)]
        .push_back(i);
  }
  for (const auto& [key, members] : series) {
    std::vector<double> cost, error, noise;
    for (size_t i : members) {
      const ResultRow& row = r.entries[i].row;
      cost.push_back(row.time_ms_median);
      error.push_back(chart_error(row));
      noise.push_back(row.time_ms_max - row.time_ms_min);
    }
    const std::vector<bool> front = pareto_front(cost, error, noise);
    for (size_t k = 0; k < members.size(); ++k) r.entries[members[k]].featured = front[k];
  }
}

// reference | estimate | |error| | signed error, as suite_runner.cpp draws it while running.
std::string draw_mosaic(const std::string& out_dir, const std::string& run_id,
                        const SuiteReportEntry& e) {
  const ResultRow& r = e.row;
  const std::string rel = "runs/" + run_id + "/mosaics/" + file_stem_for(r.run_name) + ".png";
  const fs::path png = fs::path(out_dir) / rel, ref_path = fs::path(out_dir) / e.reference_exr,
                 est_path = fs::path(out_dir) / r.estimate_file;
  if (up_to_date(png, {ref_path, est_path})) return rel;
  const AoExr ref = read_ao_exr(ref_path.string()), est = read_ao_exr(est_path.string());
  if (ref.width != est.width || ref.height != est.height)
    throw InputError(est_path.string() + ": not the size of " + ref_path.string());
  std::vector<uint8_t> mask(ref.ao.size());
  for (size_t k = 0; k < mask.size(); ++k) mask[k] = ref.covered(k) && est.covered(k);
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, "   rmse %.4f   ssim %.3f   flip %.3f",
                r.metrics.value("rmse", 0.0), r.metrics.value("ssim", 0.0),
                r.metrics.value("flip_mean", 0.0));
  fs::create_directories(png.parent_path());
  write_image(png.string(), error_mosaic(ref.width, ref.height, ref.ao.data(), est.ao.data(), mask,
                                         r.run_name + numbers));
  return rel;
}

}  // namespace

bool up_to_date(const fs::path& target, const std::vector<fs::path>& sources) {
  std::error_code ec;
  const auto t = fs::last_write_time(target, ec);
  if (ec) return false;
  for (const auto& s : sources)
    if (fs::last_write_time(s, ec) > t || ec) return false;
  return true;
}

SuiteReport with_featured_mosaics(const std::string& out_dir, const SuiteReport& report) {
  SuiteReport r = report;
  bool any = false;
  for (const auto& e : r.entries) any = any || e.featured;
  if (!any) {
    r.sweep = true;
    feature_fronts(r);
  }
  for (auto& e : r.entries)
    if (e.featured && e.row.status == "ok" && e.mosaic_png.empty() &&
        !e.row.estimate_file.empty() && !e.reference_exr.empty())
      e.mosaic_png = draw_mosaic(out_dir, r.context.run_id, e);
  return r;
}

}  // namespace aoeval
