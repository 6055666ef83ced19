// The dashboard's pictures: new | baseline | difference PNGs from the runs' estimate EXRs (through
// harness/error_maps: grey AO panels and the diverging signed map), and the history charts of the
// tracked figures (reports/plot.h, matplotlib), rendered a few at a time.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "base/errors.h"
#include "drawing/error_maps.h"
#include "drawing/plot.h"
#include "harness/results/result_row.h"
#include "reports/dashboard.h"
#include "scenes/ao_exr.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::string short_commit(const RunContext& r) {
  return r.git_commit.size() >= 7 && r.git_commit != "unknown" ? r.git_commit.substr(0, 7) : "?";
}

// "3f9a1c2 05-01 12:34": commit and start time, the x tick of a history chart.
std::string run_label(const RunContext& r) {
  const std::string when = r.started.size() >= 16 ? r.started.substr(5, 11) : r.started;
  std::string label = short_commit(r) + "\n" + when;
  std::replace(label.begin(), label.end(), 'T', ' ');
  return label;
}

const ResultRow* find_row(const std::vector<ResultRow>& rows, const RowReport& rep) {
  const ResultRow* loose = nullptr;
  int loose_count = 0;
  for (const auto& r : rows) {
    if (r.status != "ok") continue;
    if (r.run_name == rep.run_name) return &r;
    if (r.estimator == rep.estimator && r.scene == rep.scene && r.view == rep.view &&
        std::to_string(r.width) + "x" + std::to_string(r.height) == rep.resolution) {
      loose = &r;
      ++loose_count;
    }
  }
  return loose_count == 1 ? loose : nullptr;
}

// " R:0.5 Nd:8": the parameters a row's run name sets, which tell apart the rows of one group.
std::string set_params(const RowReport& rep) {
  std::string out, part;
  size_t start = rep.run_name.find('/');
  while (start != std::string::npos) {
    const size_t end = rep.run_name.find('/', start + 1);
    part = rep.run_name.substr(start + 1, end == std::string::npos ? end : end - start - 1);
    start = end;
    if (part.find(':') == std::string::npos || part.rfind("scene:", 0) == 0 ||
        part.rfind("view:", 0) == 0)
      continue;
    out += " " + part;
  }
  return out;
}

double figure_of(const ResultRow& r, const std::string& figure, bool* ok) {
  if (figure == "time_ms_median") return r.time_ms_median;
  const auto it = r.metrics.find(figure);
  *ok = it != r.metrics.end() && it->is_number();
  return *ok ? it->get<double>() : 0.0;
}

}  // namespace

std::string estimate_path(const ResultRow& row, const RunContext& run) {
  if (row.estimate_file.empty()) return "";
  const fs::path file(row.estimate_file);
  if (file.is_absolute()) return file.string();
  if (run.output_dir.empty()) return "";
  return (fs::path(run.output_dir) / file).string();
}

std::optional<double> write_row_images(RowReport& row, const AoPlanes& before,
                                       const AoPlanes& after, const std::string& out_dir) {
  const fs::path rel = fs::path("images") / file_stem_for(row.run_name);
  fs::create_directories(fs::path(out_dir) / rel);
  auto put = [&](const char* name, const OIIO::ImageBuf& image) {
    write_image((fs::path(out_dir) / rel / name).string(), image);
    return (rel / name).string();
  };
  row.new_png = put("new.png", ao_image(after.w, after.h, after.ao.data(), after.covered, "new"));
  row.baseline_png = put(
      "baseline.png", ao_image(before.w, before.h, before.ao.data(), before.covered, "baseline"));
  if (before.w != after.w || before.h != after.h) {
    row.image_note = "the images differ in size: no difference image";
    return std::nullopt;
  }
  std::vector<uint8_t> both(before.covered.size());
  double sum = 0.0;
  size_t count = 0;
  for (size_t k = 0; k < both.size(); ++k) {
    both[k] = before.covered[k] && after.covered[k];
    if (!both[k]) continue;
    const double e = static_cast<double>(after.ao[k]) - before.ao[k];
    if (!std::isfinite(e)) continue;
    sum += e * e;
    ++count;
  }
  row.diff_png =
      put("difference.png", signed_error_map(after.w, after.h, before.ao.data(), after.ao.data(),
                                             both, 0.0f, nullptr, "new \xE2\x88\x92 baseline"));
  if (count == 0) return std::nullopt;
  return std::sqrt(sum / static_cast<double>(count));
}

std::vector<GroupCharts> write_history_charts(
    const Dashboard& d, const std::vector<std::pair<RunContext, std::vector<ResultRow>>>& history,
    const std::string& out_dir) {
  // Groups in page order (failures first): the first row of each (estimator, scene) places it.
  std::vector<GroupCharts> groups;
  std::map<std::string, std::vector<const RowReport*>> members;
  for (const auto& rep : d.rows) {
    if (!rep.after) continue;
    const std::string key = rep.estimator + "\n" + rep.scene;
    if (!members.count(key)) groups.push_back({rep.estimator, rep.scene, {}});
    members[key].push_back(&rep);
  }
  std::vector<std::string> labels;
  for (const auto& [run, rows] : history) {
    std::string label = run_label(run);
    if (d.before_run && run.run_id == d.before_run->run_id) label += "\nbaseline";
    if (run.run_id == d.after_run.run_id) label += "\nnew";
    labels.push_back(label);
  }
  const fs::path charts_dir = fs::path(out_dir) / "charts";
  fs::create_directories(charts_dir);
  std::vector<std::pair<PlotSpec, std::string>> charts;
  for (auto& g : groups) {
    const auto& reps = members[g.estimator + "\n" + g.scene];
    std::vector<std::string> figures = {"rmse_excess", "time_ms_median"};
    if (d.history_searched) figures.insert(figures.begin() + 1, "mean");
    for (const std::string& figure : figures) {
      PlotSpec spec;
      spec.title = g.estimator + " on " + g.scene + ": " + figure;
      spec.x_label = "run (commit, UTC start)";
      spec.y_label = figure == "time_ms_median" ? "median time (ms)"
                     : figure == "mean"         ? "mean AO of the estimate"
                                                : figure;
      spec.categories = labels;
      spec.width_in = 5.6;
      spec.height_in = 3.2;
      spec.dpi = 90;
      PlotSeries steps;  // the runs where a series stepped (dashboard_history.cpp)
      steps.kind = "scatter";
      steps.marker = "v";
      steps.colour = "#d62728";
      steps.label = "step";
      for (const RowReport* rep : reps) {
        PlotSeries s;
        s.kind = "line";
        s.marker = "o";
        // Legend only where it stays readable (a sweep can put dozens of rows in one group).
        if (reps.size() <= 6) s.label = rep->view + " " + rep->resolution + set_params(*rep);
        for (size_t i = 0; i < history.size(); ++i) {
          const ResultRow* r = find_row(history[i].second, *rep);
          bool ok = true;
          double v = 0.0;
          if (r && figure == "mean") {
            const auto it = d.mean_ao.find(history[i].first.run_id + "|" + r->run_name);
            ok = it != d.mean_ao.end();
            if (ok) v = it->second;
          } else if (r) {
            v = figure_of(*r, figure, &ok);
          }
          if (!r || !ok || !std::isfinite(v)) continue;
          s.x.push_back(static_cast<double>(i));
          s.y.push_back(v);
          for (const auto& step : d.steps)
            if (step.series == rep->run_name && step.figure == figure &&
                step.run.run_id == history[i].first.run_id) {
              steps.x.push_back(static_cast<double>(i));
              steps.y.push_back(v);
            }
        }
        if (!s.x.empty()) spec.series.push_back(s);
      }
      if (!steps.x.empty()) spec.series.push_back(steps);
      const std::string name = file_stem_for(g.estimator + "/" + g.scene) + "__" + figure + ".png";
      charts.emplace_back(spec, (charts_dir / name).string());
      g.charts.push_back((fs::path("charts") / name).string());
    }
  }
  try {
    render_plots_on_every_core(charts);  // one plot.py process per core, each drawing its share
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("dashboard charts: ") + e.what());
  }
  return groups;
}

}  // namespace aoeval
