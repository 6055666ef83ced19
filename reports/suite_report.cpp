#include "reports/suite_report.h"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "harness/results/machine_class.h"
#include "harness/results/metric_table.h"
#include "reports/html.h"
#include "reports/page_assets.h"
#include "reports/suite_report_charts.h"
#include "reports/suite_report_leaderboard.h"
#include "reports/suite_report_mosaics.h"
#include "reports/suite_report_sequences.h"
#include "reports/viewer.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

Html metric(const nlohmann::json& metrics, const std::string& key) {
  const auto it = metrics.find(key);
  if (it == metrics.end() || it->is_null()) return Html("&ndash;");
  return it->is_number() ? number(it->get<double>()) : text(it->dump());
}

void append_listed(std::string& list, const char* separator, const std::string& item) {
  if (!list.empty()) list.append(separator);
  list.append(item);
}

Html link(const std::string& href, const std::string& label) {
  if (href.empty()) return {};
  return Html("<a href=\"") << url(href) << "\">" << text(label) << "</a>";
}

// The view's name is the user's (issue 48: it was written raw here): text, like every name.
Html view_of(const ResultRow& r) {
  return text(r.view) << " " << r.width << "&times;" << r.height;
}

// {"weighting":"cosine","dmax":null,"falloff":"none"} -> "cosine, unbounded";
// {"weighting":"cosine","dmax":1.0,"falloff":"sqrt"} -> "cosine, dmax 1, sqrt falloff".
std::string definition_text(const std::string& definition) {
  const auto j = nlohmann::json::parse(definition, nullptr, false);
  if (!j.is_object()) return definition;
  std::string text = j.value("weighting", std::string("?"));
  const auto dmax = j.find("dmax");
  if (dmax == j.end() || !dmax->is_number()) return text + ", unbounded";
  char dmax_text[48];
  std::snprintf(dmax_text, sizeof dmax_text, "%.4g", dmax->get<double>());
  text += std::string(", dmax ") + dmax_text;
  const std::string falloff = j.value("falloff", std::string("none"));
  return falloff == "none" ? text : text + ", " + falloff + " falloff";
}

void summary(Html& h, const SuiteReport& r, const std::vector<std::string>& scenes,
             const std::vector<EstimatorChart>& charts) {
  std::set<std::string> references;
  size_t ok = 0;
  for (const auto& e : r.entries) {
    if (e.row.status == "ok") ++ok;
    references.insert(e.row.reference.dump());
  }
  std::string scene_list, estimator_list, reference_list;
  for (const auto& s : scenes) append_listed(scene_list, ", ", s);
  for (const auto& c : charts)
    append_listed(estimator_list, ", ", c.estimator + " (" + std::to_string(c.rows.size()) + ")");
  for (const auto& ref : references) {
    const auto j = nlohmann::json::parse(ref);
    append_listed(reference_list, "; ",
                  std::to_string(j.value("spp", 0)) + " spp, " +
                      j.value("sampler", std::string("?")) + " sampler, seed " +
                      std::to_string(j.value("seed", 0)));
  }
  std::string sets;
  for (const auto& s : r.overrides) append_listed(sets, " ", std::string("--set ").append(s));
  auto row = [&](Literal k, const Html& v) {
    h << "<tr><th>" << k << "</th><td class=\"l\">" << v << "</td></tr>\n";
  };
  h << "<table class=\"summary\" id=\"summary\">\n";
  row("suite", text(r.suite + " (" + r.suite_file + ")"));
  if (!sets.empty()) row("overrides", text(sets));
  row("scenes", text(std::to_string(scenes.size()) + ": " + scene_list));
  row("estimators", text(std::to_string(charts.size()) + " (rows): " + estimator_list));
  row("rows", text(std::to_string(r.entries.size()) + " (" + std::to_string(ok) + " ok, " +
                   std::to_string(r.entries.size() - ok) + " skipped)"));
  row("references", text("Embree ray-traced, " + reference_list));
  row("run id", text(r.context.run_id));
  row("started", text(r.context.started));
  row("git commit", text(r.context.git_commit));
  row("aoeval version", text(r.context.aoeval_version));
  std::vector<ResultRow> all_rows;
  std::set<std::string> nodes;
  for (const auto& e : r.entries) {
    all_rows.push_back(e.row);
    if (!e.row.machine.empty()) nodes.insert(e.row.machine);
  }
  const std::vector<std::string> classes = machine_classes(all_rows);
  if (nodes.size() <= 1) {
    row("machine", text(r.context.machine));
  } else {  // merged from several nodes (aoeval merge, CONTRACT §9)
    std::string node_list, class_list;
    for (const auto& n : nodes) append_listed(node_list, "; ", n);
    for (const auto& c : classes) append_listed(class_list, "; ", c);
    row("machines", text(std::to_string(nodes.size()) + " nodes: " + node_list));
    row("machine classes",
        text(class_list + (classes.size() > 1 ? ". Times are compared only within a machine class "
                                                "(CPU model, cores, device): see each timing table."
                                              : ". One class: the times compare across nodes.")));
  }
  row("Embree", text(r.context.embree_version));
  row("wall time",
      r.wall_s > 0.0 ? number(r.wall_s, "%.1f") + " s (before the report)" : Html("not recorded"));
  row("files", link("results.csv", "results.csv") + " " + link("results.json", "results.json") +
                   " " + link(r.gbuffer_gallery, "G-buffer gallery"));
  h << "</table>\n";
}

// The mosaic inside its viewer (CONTRACT §11): the PNG is what a reader without JavaScript sees.
Html mosaic_html(const std::string& out_dir, const SuiteReportEntry& e) {
  const ResultRow& r = e.row;
  const Html image = Html("<a href=\"") << url(r.estimate_file) << "\"><img class=\"mosaic\" src=\""
                                        << url(e.mosaic_png) << "\" loading=\"lazy\" alt=\""
                                        << attr(r.run_name) << "\"></a>";
  std::error_code ec;
  const fs::path dir(out_dir);
  if (r.estimate_file.empty() || e.reference_exr.empty() ||
      !fs::exists(dir / r.estimate_file, ec) || !fs::exists(dir / e.reference_exr, ec))
    return image;  // images no longer there: the static mosaic alone
  return compare_viewer(out_dir, e.reference_exr, r.estimate_file, "reference,estimate", image);
}

// The viewer data of every mosaic's pair, written in parallel before the page asks for them one by
// one (compare_viewer then finds each up to date): each file once (a reference is shared by the
// points of its view and definition; two threads must not write one file).
void write_mosaic_viewer_data(const std::string& out_dir, const SuiteReport& report) {
  std::set<std::string> references, estimates;
  std::error_code ec;
  const fs::path dir(out_dir);
  for (const auto& e : report.entries) {
    const ResultRow& r = e.row;
    if (r.status != "ok" || e.mosaic_png.empty() || r.estimate_file.empty() ||
        e.reference_exr.empty() || !fs::exists(dir / r.estimate_file, ec) ||
        !fs::exists(dir / e.reference_exr, ec))
      continue;
    references.insert(e.reference_exr);
    estimates.insert(r.estimate_file);
  }
  std::vector<std::pair<std::string, const std::vector<std::string>*>> files;
  for (const auto& f : references) files.emplace_back(f, &reference_viewer_channels());
  for (const auto& f : estimates) files.emplace_back(f, &estimate_viewer_channels());
  tbb::parallel_for(size_t{0}, files.size(), [&](size_t i) {
    write_viewer_data(out_dir, {files[i].first}, *files[i].second);
  });
}

void scene_section(Html& h, const std::string& out_dir, const std::string& scene,
                   const std::vector<const SuiteReportEntry*>& rows) {
  h << "<section class=\"scene\" id=\"scene-" << attr(slug(scene)) << "\"><h2>Scene " << text(scene)
    << "</h2>\n";
  for (const auto* e : rows) {
    const ResultRow& r = e->row;
    if (r.status != "ok" || e->mosaic_png.empty()) continue;
    h << "<figure id=\"mosaic-" << attr(slug(r.run_name)) << "\">" << mosaic_html(out_dir, *e)
      << "\n<figcaption><b>" << text(r.estimator) << "</b> " << text(params_of(r)) << ", view "
      << view_of(r)
      << ": reference | estimate | |estimate &minus; reference| | estimate &minus; reference. "
      << link(r.estimate_file, "estimate EXR") << " &middot; "
      << link(e->reference_exr, "reference EXR") << " (" << text(definition_text(r.definition))
      << ") &middot; " << link(e->true_reference_exr, "true-AO reference EXR")
      << "</figcaption></figure>\n";
  }
  h << "<h3>Metrics</h3>\n<table class=\"metrics\"><tr><th class=\"l\">estimator</th><th "
       "class=\"l\">parameters</th><th class=\"l\">view</th><th class=\"l\">matched "
       "definition</th>";
  // The columns the metric table marks for the report: image keys against the matched reference,
  // then against true AO, then the bent-normal keys (blank for estimators without them).
  std::vector<std::pair<std::string, const nlohmann::json ResultRow::*>> columns;
  for (const MetricFamily family : {MetricFamily::image, MetricFamily::bent}) {
    for (const MetricDef& m : metric_table())
      if (m.family == family && m.report_matched) columns.emplace_back(m.key, &ResultRow::metrics);
    if (family == MetricFamily::image)
      for (const MetricDef& m : metric_table())
        if (m.family == family && m.report_true)
          columns.emplace_back("true_" + m.key, &ResultRow::true_metrics);
  }
  for (const auto& c : columns) h << "<th>" << text(c.first) << "</th>";
  h << "</tr>\n";
  for (const auto* e : rows) {
    const ResultRow& r = e->row;
    h << "<tr><td class=\"l\">" << text(r.estimator) << "</td><td class=\"l\">"
      << text(params_of(r)) << "</td><td class=\"l\">" << view_of(r) << "</td><td class=\"l\">"
      << text(definition_text(r.definition)) << "</td>";
    if (r.status != "ok") {
      h << "<td colspan=\"" << columns.size() << "\" class=\"l skipped\">" << text(r.status)
        << "</td></tr>\n";
      continue;
    }
    for (const auto& [key, metrics] : columns) {
      const std::string bare = key.rfind("true_", 0) == 0 ? key.substr(5) : key;
      h << "<td>" << metric(r.*metrics, bare.c_str()) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
  std::set<std::string> passes;
  std::vector<ResultRow> timed;
  for (const auto* e : rows) {
    for (const auto& [pass, ms] : e->row.pass_ms) passes.insert(pass);
    if (e->row.status == "ok") timed.push_back(e->row);
  }
  // Rows merged from different kinds of machine (issue 19): times compare within a class only.
  const bool classes = machine_classes(timed).size() > 1;
  h << "<h3>Timing (ms)</h3>\n";
  if (classes)
    h << "<p class=\"note\">These rows were measured on more than one machine class; compare "
         "times only between rows of the same class.</p>\n";
  h << "<table class=\"timing\"><tr><th class=\"l\">estimator</th><th "
       "class=\"l\">parameters</th><th class=\"l\">view</th>"
    << (classes ? Html("<th class=\"l\">machine class</th>") : Html())
    << "<th>median</th><th>min</th><th>max</th><th>reps</th><th>precompute</th>";
  for (const auto& p : passes) h << "<th>" << text(p) << "</th>";
  h << "</tr>\n";
  for (const auto* e : rows) {
    const ResultRow& r = e->row;
    if (r.status != "ok") continue;
    h << "<tr><td class=\"l\">" << text(r.estimator) << "</td><td class=\"l\">"
      << text(params_of(r)) << "</td><td class=\"l\">" << view_of(r) << "</td>";
    if (classes) h << "<td class=\"l\">" << text(machine_class(r)) << "</td>";
    h << "<td>" << number(r.time_ms_median) << "</td><td>" << number(r.time_ms_min) << "</td><td>"
      << number(r.time_ms_max) << "</td><td>" << r.repetitions << "</td><td>"
      << number(r.precompute_ms) << "</td>";
    for (const auto& p : passes) {
      const auto it = r.pass_ms.find(p);
      h << "<td>" << (it == r.pass_ms.end() ? Html("&ndash;") : number(it->second)) << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n</section>\n";
}

void estimator_section(Html& h, const EstimatorChart& c) {
  h << "<section class=\"estimator\" id=\"estimator-" << attr(slug(c.estimator))
    << "\"><h2>Estimator " << text(c.estimator) << "</h2>\n";
  if (c.png.empty()) {
    h << "<p class=\"skipped\">Every run of it was "
      << text(c.rows.empty() ? std::string() : c.rows.front()->row.status) << "</p>\n</section>\n";
    return;
  }
  h << "<figure><a href=\"" << url(c.png + ".plot.json") << "\"><img class=\"chart\" src=\""
    << url(c.png) << "\" loading=\"lazy\" alt=\"" << attr(c.estimator)
    << ": error against time\"></a><figcaption>" << text(kChartMetric)
    << " (against true AO, the leaderboard's one truth; a sequence point: its true "
       "steady_rmse_excess) against the median time per frame, one series per scene view; the "
       "Pareto front (no "
       "other point of the series is both at least as fast and more accurate, times closer than "
       "their repetitions' interquartile range counting as equal) is marked and listed in bold "
       "below. The image "
       "links to the plotted data, each run name to its estimate "
       "EXR.</figcaption></figure>\n";
  h << "<details><summary>" << c.rows.size() << (c.rows.size() == 1 ? Html(" row") : Html(" rows"))
    << "</summary>\n<table class=\"sweep\"><tr><th class=\"l\">run</th><th>" << text(kChartMetric)
    << "</th><th>rmse</th><th>true_rmse</th><th>median ms</th><th>Pareto</th></tr>\n";
  for (size_t i = 0; i < c.rows.size(); ++i) {
    const ResultRow& r = c.rows[i]->row;
    h << "<tr" << (c.on_front[i] ? Html(" class=\"front\"") : Html()) << "><td class=\"l\">"
      << (r.estimate_file.empty() ? text(r.run_name) : link(r.estimate_file, r.run_name))
      << "</td>";
    if (r.status != "ok") {
      h << "<td colspan=\"5\" class=\"l skipped\">" << text(r.status) << "</td></tr>\n";
      continue;
    }
    h << "<td>" << number(true_score(r)) << "</td><td>" << metric(r.metrics, "rmse") << "</td><td>"
      << metric(r.true_metrics, "rmse") << "</td><td>" << number(r.time_ms_median) << "</td><td>"
      << (c.on_front[i] ? Html("yes") : Html()) << "</td></tr>\n";
  }
  h << "</table></details>\n</section>\n";
}

}  // namespace

std::string write_suite_report(const std::string& out_dir, const SuiteReport& report) {
  // A sweep features no point of its own: its Pareto-front points are shown (mosaics drawn here).
  const SuiteReport r = with_featured_mosaics(out_dir, report);
  const std::vector<EstimatorChart> charts = write_estimator_charts(out_dir, r);
  write_mosaic_viewer_data(out_dir, r);
  const Html sequences = sequence_sections(out_dir, r);
  std::vector<std::string> scenes;
  std::map<std::string, std::vector<const SuiteReportEntry*>> featured;
  for (const auto& e : r.entries) {
    if (!featured.count(e.row.scene)) scenes.push_back(e.row.scene);
    auto& list = featured[e.row.scene];
    if (e.featured) list.push_back(&e);
  }
  // Mosaics and metrics tables rank on the leaderboard's one truth: within each scene view (views
  // in order of appearance), by true_score (a sequence: true steady_rmse_excess), skipped last.
  for (auto& [scene, list] : featured) {
    std::map<std::string, size_t> view_order;
    for (const auto* e : list)
      view_order.emplace(
          e->row.view + "/" + std::to_string(e->row.width) + "x" + std::to_string(e->row.height),
          view_order.size());
    const auto view_of_entry = [&](const SuiteReportEntry* e) {
      return view_order[e->row.view + "/" + std::to_string(e->row.width) + "x" +
                        std::to_string(e->row.height)];
    };
    std::stable_sort(list.begin(), list.end(), [&](const auto* a, const auto* b) {
      const size_t va = view_of_entry(a), vb = view_of_entry(b);
      if (va != vb) return va < vb;
      const double x = true_score(a->row), y = true_score(b->row);
      return !std::isnan(x) && (std::isnan(y) || x < y);
    });
  }
  Html h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << content_security_policy() << "<title>aoeval " << text(r.suite) << " suite, run "
    << text(r.context.run_id) << "</title>\n"
    << page_stylesheet(out_dir, "suite.css") << write_viewer_assets(out_dir)
    << "</head><body>\n<h1>aoeval: " << text(r.suite) << (r.sweep ? Html(" sweep") : Html(" suite"))
    << "</h1>\n";
  h << leaderboard_html(r.entries, scenes);
  summary(h, r, scenes, charts);
  h << "<nav>Scenes: ";
  for (const auto& s : scenes)
    h << "<a href=\"#scene-" << attr(slug(s)) << "\">" << text(s) << "</a>";
  h << "<br>Estimators: ";
  for (const auto& c : charts)
    h << "<a href=\"#estimator-" << attr(slug(c.estimator)) << "\">" << text(c.estimator) << "</a>";
  if (!sequences.empty()) h << "<br><a href=\"#sequences\">Sequences (AO over time)</a>";
  h << "</nav>\n<p>Each scene shows every estimator's featured run (its default point unless the "
       "suite says otherwise; in a sweep, the points on its Pareto fronts). A mosaic opens in the "
       "viewer (click it: zoom to pixels, probe values, flip A/B, exposure; press ? there for its "
       "keys). Within each scene view, mosaics and metrics rows are in the leaderboard's order: by "
       "true rmse_excess (against true AO; a sequence point: its true steady_rmse_excess), the "
       "one truth every estimator shares. Metrics compare the estimate with the reference of the "
       "AO "
       "definition the estimator declares (&ldquo;matched&rdquo;) and, as true_*, with unbounded "
       "cosine AO; rmse_excess is the RMSE with the reference's own Monte-Carlo noise removed. "
       "Estimators with bent normals add bent_angle_mean and bent_angle_p95 (degrees between "
       "their bent normal and the reference's) and bent_angle_excess (the rms angle with the "
       "reference bent normal's own noise removed). "
       "Each mosaic links to the estimate EXR; its caption links to the reference EXRs.</p>\n";
  for (const auto& s : scenes) scene_section(h, out_dir, s, featured[s]);
  h << sequences;
  for (const auto& c : charts) estimator_section(h, c);
  h << "</body></html>\n";
  const std::string page = (fs::path(out_dir) / "index.html").string();
  write_text(page, h.str());
  return page;
}

}  // namespace aoeval
