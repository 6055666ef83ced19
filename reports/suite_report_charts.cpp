#include "reports/suite_report_charts.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "base/param_text.h"
#include "base/summary.h"
#include "drawing/plot.h"
#include "harness/results/pareto.h"
#include "harness/results/result_row.h"
#include "reports/suite_report_leaderboard.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// The parameters whose values differ between `rows` ("derived" is not a parameter).
std::vector<std::string> swept_parameters(const std::vector<const SuiteReportEntry*>& rows) {
  std::vector<std::string> swept;
  if (rows.empty()) return swept;
  for (const auto& [key, value] : rows.front()->row.params.items()) {
    if (key == "derived") continue;
    for (const auto* e : rows)
      if (!e->row.params.contains(key) || e->row.params[key] != value) {
        swept.push_back(key);
        break;
      }
  }
  return swept;
}

std::string point_label(const ResultRow& row, const std::vector<std::string>& swept) {
  std::string label;
  for (const auto& key : swept) {
    if (!label.empty()) label += " ";
    label += key + "=" + format_param_value(row.params[key]);
  }
  return label;
}

void append_listed(std::string& list, const char* separator, const std::string& item) {
  if (!list.empty()) list.append(separator);
  list.append(item);
}

}  // namespace

std::vector<EstimatorChart> write_estimator_charts(const std::string& out_dir,
                                                   const SuiteReport& report) {
  std::vector<EstimatorChart> charts;
  std::map<std::string, size_t> index;
  for (const auto& e : report.entries) {
    auto [it, fresh] = index.emplace(e.row.estimator, charts.size());
    if (fresh) {
      charts.emplace_back();
      charts.back().estimator = e.row.estimator;
      charts.back().metric = kChartMetric;
    }
    charts[it->second].rows.push_back(&e);
  }
  const std::string plots_rel = "runs/" + report.context.run_id + "/plots";
  std::vector<std::pair<PlotSpec, std::string>> plots;
  for (auto& chart : charts) {
    chart.on_front.assign(chart.rows.size(), false);
    std::vector<const SuiteReportEntry*> ok;
    for (const auto* e : chart.rows)
      if (e->row.status == "ok") ok.push_back(e);
    chart.swept = swept_parameters(ok);
    if (ok.empty()) continue;
    // One series per scene view and resolution, in order of first appearance.
    std::vector<std::string> series_keys;
    std::map<std::string, std::vector<size_t>> members;  // key -> indices into chart.rows
    for (size_t i = 0; i < chart.rows.size(); ++i) {
      const ResultRow& r = chart.rows[i]->row;
      if (r.status != "ok") continue;
      const std::string key =
          r.scene + "/" + r.view + " " + std::to_string(r.width) + "x" + std::to_string(r.height);
      if (!members.count(key)) series_keys.push_back(key);
      members[key].push_back(i);
    }
    PlotSpec spec;
    spec.title = chart.estimator + ": error against time";
    spec.x_label = "time per frame, median (ms)";
    spec.y_label = std::string(kChartMetric) + " (against true AO; a sequence: steady)";
    spec.width_in = 7.5;
    spec.height_in = 4.6;
    if (!chart.swept.empty()) {
      std::string swept;
      for (const auto& k : chart.swept) append_listed(swept, ", ", k);
      spec.title += " (swept: " + swept + ")";
    }
    for (const auto& key : series_keys) {
      PlotSeries s;
      s.label = key;
      s.kind = "scatter";
      std::vector<double> noise;  // the robust spread of the timed repetitions
      std::vector<const SuiteReportEntry*> series_rows;
      for (size_t i : members[key]) {
        const ResultRow& r = chart.rows[i]->row;
        s.x.push_back(r.time_ms_median);
        s.y.push_back(true_score(r));
        noise.push_back(pareto_time_noise(r));
        series_rows.push_back(chart.rows[i]);
      }
      const std::vector<bool> front = pareto_front(s.x, s.y, noise);
      const std::vector<std::string> swept = swept_parameters(series_rows);
      for (size_t k = 0; k < front.size(); ++k) {
        const size_t i = members[key][k];
        chart.on_front[i] = front[k];
        s.highlight.push_back(front[k]);
        s.point_labels.push_back(front[k] ? point_label(chart.rows[i]->row, swept) : "");
      }
      spec.series.push_back(std::move(s));
    }
    // Log time where the times span a factor of 4 or more; a narrower span reads better linear.
    double lo = INFINITY, hi = 0.0;
    for (const auto& s : spec.series)
      for (double x : s.x)
        if (x > 0.0) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
    spec.log_x = hi >= 4.0 * lo;
    if (!spec.log_x) spec.x_label += ", linear axis";
    chart.png = plots_rel + "/" + file_stem_for(chart.estimator) + ".png";
    plots.emplace_back(std::move(spec), (fs::path(out_dir) / chart.png).string());
  }
  fs::create_directories(fs::path(out_dir) / plots_rel);
  try {
    render_plots_on_every_core(plots);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("suite report charts: ") + e.what());
  }
  return charts;
}

}  // namespace aoeval
