#include "reports/suite_report_leaderboard.h"

#include <algorithm>
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

// What a row ranks by: rmse_excess, or for a sequence point (CONTRACT §10) its steady state,
// steady_rmse_excess (the last frame alone would reward a history that is right only at the end).
std::string ranked_key(const ResultRow& r) {
  const auto frames = r.metrics.find("seq_frames");
  return frames != r.metrics.end() && frames->is_number() ? "steady_rmse_excess" : "rmse_excess";
}

namespace {

double number_in(const ResultRow& r, const nlohmann::json& metrics) {
  const auto it = metrics.find(ranked_key(r));
  return r.status == "ok" && it != metrics.end() && it->is_number() ? it->get<double>()
                                                                    : std::nan("");
}

}  // namespace

// The score every estimator of a scene view is ranked on: against the one truth they share, true
// AO (the unbounded cosine reference, CONTRACT §3: the row's true_ keys). Each estimator's matched
// score (against the reference of the definition it declares) is shown beside it but not ranked:
// a bounded estimator scores well against its own bounded reference while missing most of the
// true occlusion, so ranking matched scores would mix truths.
double true_score(const ResultRow& r) {
  return number_in(r, r.true_metrics);
}

double matched_score(const ResultRow& r) {
  return number_in(r, r.metrics);
}

namespace {

std::string view_key(const ResultRow& r) {
  return r.scene + "/" + r.view + "/" + std::to_string(r.width) + "x" + std::to_string(r.height);
}

}  // namespace

Html leaderboard_html(const std::vector<SuiteReportEntry>& entries,
                      const std::vector<std::string>& scenes) {
  // Rows: one per featured configuration (estimator and its explicit parameters), in order.
  std::vector<std::string> labels;
  std::map<std::string, std::map<std::string, std::vector<const SuiteReportEntry*>>> cells;
  std::map<std::string, double> best;  // per scene view: the least true score
  for (const auto& e : entries) {
    if (!e.featured) continue;
    const std::string params = params_of(e.row);
    const std::string label = e.row.estimator + (params == "defaults" ? "" : " " + params);
    if (!cells.count(label)) labels.push_back(label);
    cells[label][e.row.scene].push_back(&e);
    const double v = true_score(e.row);
    if (!std::isnan(v)) {
      auto [it, fresh] = best.emplace(view_key(e.row), v);
      if (!fresh) it->second = std::min(it->second, v);
    }
  }
  if (labels.empty()) return {};
  // The rows' order: by mean rank on the true score over the scene views (each view ranks its
  // estimators 1, 2, ...; a missing or skipped cell ranks after every scored one), ties in order
  // of appearance. With one scene view it is the order of the true score itself.
  std::map<std::string, std::vector<std::pair<double, std::string>>> by_view;
  for (const auto& label : labels)
    for (const auto& [scene, list] : cells[label])
      for (const auto* e : list) by_view[view_key(e->row)].emplace_back(true_score(e->row), label);
  std::map<std::string, double> rank_sum;
  for (auto& [view, scores] : by_view) {
    std::stable_sort(scores.begin(), scores.end(), [](const auto& a, const auto& b) {
      return !std::isnan(a.first) && (std::isnan(b.first) || a.first < b.first);
    });
    std::map<std::string, size_t> rank;
    for (size_t i = 0; i < scores.size(); ++i) rank.emplace(scores[i].second, i + 1);
    for (const auto& label : labels)
      rank_sum[label] += rank.count(label) ? rank[label] : labels.size() + 1;
  }
  std::stable_sort(labels.begin(), labels.end(), [&](const std::string& a, const std::string& b) {
    return rank_sum[a] < rank_sum[b];
  });
  Html h;
  h << "<h2 id=\"leaderboard\">Leaderboard</h2>\n<p>Each estimator's featured point per scene, "
       "ranked on one truth: <b>true</b> is rmse_excess against true AO (the unbounded cosine "
       "reference every estimator of a scene view shares), <b>matched</b> the same against the "
       "reference of the definition the estimator declares (shown, not ranked: a bounded "
       "estimator scores well against its own bounded reference), and median ms per frame. A "
       "sequence point ranks by its steady state, steady_rmse_excess (true and matched). "
       "&#9733; marks the least true score of a scene view. Rows are in order of their mean rank "
       "on the true score over the scene views (with one view: the order of the true score). "
       "Click a header to sort; a value links to its mosaic.</p>\n"
       "<table class=\"leaderboard sortable\"><thead><tr><th class=\"l\" rowspan=\"2\" "
       "data-sort=\"0\" data-type=\"text\">estimator</th>";
  for (const auto& s : scenes) h << "<th colspan=\"3\">" << text(s) << "</th>";
  h << "</tr>\n<tr>";
  for (size_t k = 0; k < scenes.size(); ++k)
    h << "<th data-sort=\"" << 1 + 3 * k << "\">true</th><th data-sort=\"" << 2 + 3 * k
      << "\">matched</th><th data-sort=\"" << 3 + 3 * k << "\">ms</th>";
  h << "</tr></thead>\n<tbody>\n";
  for (const auto& label : labels) {
    h << "<tr><td class=\"l\">" << text(label) << "</td>";
    for (const auto& s : scenes) {
      const auto it = cells[label].find(s);
      if (it == cells[label].end()) {
        h << "<td></td><td></td><td></td>";
        continue;
      }
      // Several views of a scene: one line each; the first one sorts.
      Html error_cell, matched_cell, time_cell, error_v, matched_v, time_v;
      bool is_best = false, skipped = false;
      for (const auto* e : it->second) {
        const ResultRow& r = e->row;
        if (!error_cell.empty()) {
          error_cell << "<br>";
          matched_cell << "<br>";
          time_cell << "<br>";
        }
        const Html title =
            attr(r.view + " " + std::to_string(r.width) + "x" + std::to_string(r.height));
        const double v = true_score(r);
        if (std::isnan(v)) {
          skipped = skipped || error_cell.empty();
          error_cell << "<span title=\"" << attr(r.status) << "\">skipped</span>";
          matched_cell << "&ndash;";
          time_cell << "&ndash;";
          continue;
        }
        const double m = matched_score(r);
        if (std::isnan(m))
          matched_cell << "&ndash;";
        else
          matched_cell << number(m);
        const bool b = v <= best[view_key(r)];
        is_best = is_best || b;
        error_cell << "<a href=\"#mosaic-" << attr(slug(r.run_name)) << "\" title=\"" << title
                   << "\">" << number(v) << (b ? Html(" &#9733;") : Html()) << "</a>";
        time_cell << number(r.time_ms_median);
        if (error_v.empty()) {
          error_v = number(v);
          if (!std::isnan(m)) matched_v = number(m);
          time_v = number(r.time_ms_median);
        }
      }
      h << "<td"
        << (is_best   ? Html(" class=\"best\"")
            : skipped ? Html(" class=\"skipped\"")
                      : Html())
        << " data-v=\"" << error_v << "\">" << error_cell << "</td><td data-v=\"" << matched_v
        << "\">" << matched_cell << "</td><td data-v=\"" << time_v << "\">" << time_cell << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</tbody></table>\n";
  return h;
}

}  // namespace aoeval
