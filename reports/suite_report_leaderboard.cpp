#include "reports/suite_report_leaderboard.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "reports/html.h"

namespace aoeval {

std::string slug(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return o;
}

std::string params_of(const ResultRow& r) {
  const std::string& name = r.run_name;
  const auto first = name.find('/'), scene = name.find("/scene:");
  if (first == std::string::npos || scene == std::string::npos || scene <= first) return "defaults";
  return name.substr(first + 1, scene - first - 1);
}

namespace {

double rmse_excess(const ResultRow& r) {
  const auto it = r.metrics.find("rmse_excess");
  return r.status == "ok" && it != r.metrics.end() && it->is_number() ? it->get<double>()
                                                                      : std::nan("");
}

std::string view_key(const ResultRow& r) {
  return r.scene + "/" + r.view + "/" + std::to_string(r.width) + "x" + std::to_string(r.height);
}

}  // namespace

Html leaderboard_html(const std::vector<SuiteReportEntry>& entries,
                      const std::vector<std::string>& scenes) {
  // Rows: one per featured configuration (estimator and its explicit parameters), in order.
  std::vector<std::string> labels;
  std::map<std::string, std::map<std::string, std::vector<const SuiteReportEntry*>>> cells;
  std::map<std::string, double> best;  // per scene view: the least rmse_excess
  for (const auto& e : entries) {
    if (!e.featured) continue;
    const std::string params = params_of(e.row);
    const std::string label = e.row.estimator + (params == "defaults" ? "" : " " + params);
    if (!cells.count(label)) labels.push_back(label);
    cells[label][e.row.scene].push_back(&e);
    const double v = rmse_excess(e.row);
    if (!std::isnan(v)) {
      auto [it, fresh] = best.emplace(view_key(e.row), v);
      if (!fresh) it->second = std::min(it->second, v);
    }
  }
  if (labels.empty()) return {};
  Html h;
  h << "<h2 id=\"leaderboard\">Leaderboard</h2>\n<p>Each estimator's featured point per scene: "
       "rmse_excess (matched reference) and median ms per frame; &#9733; marks the least "
       "rmse_excess of a scene view. Click a header to sort; a value links to its mosaic.</p>\n"
       "<table class=\"leaderboard sortable\"><thead><tr><th class=\"l\" rowspan=\"2\" "
       "data-sort=\"0\" data-type=\"text\">estimator</th>";
  for (const auto& s : scenes) h << "<th colspan=\"2\">" << text(s) << "</th>";
  h << "</tr>\n<tr>";
  for (size_t k = 0; k < scenes.size(); ++k)
    h << "<th data-sort=\"" << 1 + 2 * k << "\">rmse_excess</th><th data-sort=\"" << 2 + 2 * k
      << "\">ms</th>";
  h << "</tr></thead>\n<tbody>\n";
  for (const auto& label : labels) {
    h << "<tr><td class=\"l\">" << text(label) << "</td>";
    for (const auto& s : scenes) {
      const auto it = cells[label].find(s);
      if (it == cells[label].end()) {
        h << "<td></td><td></td>";
        continue;
      }
      // Several views of a scene: one line each; the first one sorts.
      Html error_cell, time_cell, error_v, time_v;
      bool is_best = false, skipped = false;
      for (const auto* e : it->second) {
        const ResultRow& r = e->row;
        if (!error_cell.empty()) {
          error_cell << "<br>";
          time_cell << "<br>";
        }
        const Html title =
            attr(r.view + " " + std::to_string(r.width) + "x" + std::to_string(r.height));
        const double v = rmse_excess(r);
        if (std::isnan(v)) {
          skipped = skipped || error_cell.empty();
          error_cell << "<span title=\"" << attr(r.status) << "\">skipped</span>";
          time_cell << "&ndash;";
          continue;
        }
        const bool b = v <= best[view_key(r)];
        is_best = is_best || b;
        error_cell << "<a href=\"#mosaic-" << attr(slug(r.run_name)) << "\" title=\"" << title
                   << "\">" << number(v) << (b ? Html(" &#9733;") : Html()) << "</a>";
        time_cell << number(r.time_ms_median);
        if (error_v.empty()) {
          error_v = number(v);
          time_v = number(r.time_ms_median);
        }
      }
      h << "<td"
        << (is_best   ? Html(" class=\"best\"")
            : skipped ? Html(" class=\"skipped\"")
                      : Html())
        << " data-v=\"" << error_v << "\">" << error_cell << "</td><td data-v=\"" << time_v << "\">"
        << time_cell << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</tbody></table>\n";
  return h;
}

}  // namespace aoeval
