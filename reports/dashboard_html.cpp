// The dashboard page: a verdict banner, the summary table (failures first), then one section per
// (estimator, scene) with its history charts and, per row, the checks and the new | baseline |
// difference images (hovering the new image shows the baseline in its place). Self-contained:
// its style and script in dashboard.css and dashboard.js beside it (reports/pages/; the page's
// Content-Security-Policy allows no inline script), relative image paths, no external URL. Written
// through reports/html.h: every name is text.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <sstream>

#include "reports/dashboard.h"
#include "reports/frame_chart.h"
#include "reports/html.h"

namespace aoeval {

namespace {

Html num(double v) {
  return number(v);
}

// The verdict as a CSS class: its name with spaces as dashes ("not compared" -> "not-compared").
Html css_class(Verdict v) {
  std::string name = to_string(v);
  for (char& c : name)
    if (c == ' ') c = '-';
  return attr(name);
}

// The explicitly set parameters of a run name ("hbao-split/Nd:4/Ns:6/scene:bunny/view:main/
// 320x240" -> "Nd:4 Ns:6"): what tells apart rows of one estimator, scene and view.
std::string point_of(const std::string& run_name) {
  std::string out, part;
  std::istringstream in(run_name);
  bool first = true;
  while (std::getline(in, part, '/')) {
    const bool skip = first || part.rfind("scene:", 0) == 0 || part.rfind("view:", 0) == 0 ||
                      part.find(':') == std::string::npos;  // estimator, scene, view, WxH
    first = false;
    if (skip) continue;
    if (!out.empty()) out += ' ';
    out += part;
  }
  return out;
}

Html run_line(const RunContext& r) {
  return Html("<code>") << text(r.run_id) << "</code> &middot; commit <code>"
                        << text(r.git_commit.substr(0, 12)) << "</code> &middot; "
                        << text(r.started) << " &middot; <code>" << text(r.command)
                        << "</code> &middot; " << text(r.machine);
}

Html checks_table(const RowReport& rep) {
  Html h(
      "<table class=\"checks\"><tr><th>figure</th><th>baseline</th><th>new</th><th>verdict</th>"
      "<th>why</th></tr>\n");
  for (const auto& c : rep.checks) {
    const bool numbers = c.figure != "status";
    h << "<tr class=\"" << css_class(c.verdict) << "\"><td>" << text(c.figure) << "</td><td>"
      << (numbers ? num(c.before) : Html()) << "</td><td>" << (numbers ? num(c.after) : Html())
      << "</td><td>" << text(to_string(c.verdict)) << "</td><td>" << text(c.detail)
      << "</td></tr>\n";
  }
  return h << "</table>\n";
}

Html images(const RowReport& rep) {
  Html h;
  if (!rep.new_png.empty()) {
    h << "<div class=\"images\">\n<figure><img class=\"swap\" src=\"" << url(rep.new_png)
      << "\" data-new=\"" << url(rep.new_png) << "\" data-baseline=\"" << url(rep.baseline_png)
      << "\" loading=\"lazy\" alt=\"new estimate\"><figcaption>new (hover: baseline)"
         "</figcaption></figure>\n";
    h << "<figure><img class=\"baseline\" src=\"" << url(rep.baseline_png)
      << "\" loading=\"lazy\" alt=\"baseline "
         "estimate\"><figcaption>baseline</figcaption></figure>\n";
    if (!rep.diff_png.empty()) {
      h << "<figure><img class=\"difference\" src=\"" << url(rep.diff_png)
        << "\" loading=\"lazy\" alt=\"new minus baseline\"><figcaption>new &minus; baseline (red: "
           "new brighter, "
           "blue: new darker)</figcaption></figure>\n";
    }
    h << "</div>\n";
  }
  if (!rep.image_note.empty()) h << "<p class=\"note\">" << text(rep.image_note) << "</p>\n";
  return h;
}

// One line on the estimate's change against the baseline's (image_change.h).
Html change_line(const RowReport& rep) {
  if (!rep.change) return {};
  const ImageChange& c = *rep.change;
  char line[320];
  std::snprintf(line, sizeof line,
                "mean_shift %+.4f (limit %.4f), changed pixels %.1f %% (per-pixel threshold %.2g, "
                "noise rule: %s, %zu pixels)",
                c.mean_shift, rep.change_limit, 100.0 * c.changed_pixels, c.pixel_threshold,
                c.noise_rule.c_str(), c.pixels);
  return Html("<p class=\"change\">")
         << (rep.changed ? Html("<b>CHANGED</b>: ") : Html("estimate: "))
         << text((rep.changed ? change_phrase(c) + "; " : std::string()) + line) << "</p>\n";
}

// One line on a sequence point's frames against the baseline's (frame_change.h).
Html frames_line(const RowReport& rep) {
  if (!rep.frames) return {};
  return Html("<p class=\"frames\">frames: ")
         << text(frames_phrase(*rep.frames)) << "</p>\n"
         << frame_chart(rep.before_frames, rep.after_frames, "time_ms");
}

Html group_anchor(const std::string& estimator, const std::string& scene) {
  std::string a = "group-" + estimator + "-" + scene;
  for (char& ch : a)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-') ch = '-';
  return attr(a);
}

// The "Changed" section: every changed row with its parameters, its change and its images.
Html changed_section(const Dashboard& d) {
  if (d.changed == 0) return {};
  Html h;
  h << "<h2 id=\"changed\">Changed (" << d.changed
    << ")</h2>\n<p class=\"note\">The estimate itself moved against the baseline's "
       "(mean of new &minus; baseline AO beyond change_mean_shift and its noise), "
       "whatever its error did.</p>\n";
  for (const auto& rep : d.rows) {
    if (!rep.changed) continue;
    h << "<article class=\"row changed\"><h3>" << text(rep.estimator) << " <code>"
      << text(rep.params_text) << "</code> on " << text(rep.scene) << ", " << text(rep.view) << " "
      << text(rep.resolution) << ": " << text(change_phrase(*rep.change))
      << (rep.change_fails ? Html(" (fails)") : Html(" (warns)")) << "</h3>\n"
      << change_line(rep) << images(rep) << "</article>\n";
  }
  return h;
}

// The "Steps" section of --history: one line per step, linking to its group's charts.
Html steps_section(const Dashboard& d) {
  if (!d.history_searched) return {};
  Html h;
  h << "<h2 id=\"steps\">Steps over the last " << d.history_size << " runs (" << d.steps.size()
    << ")</h2>\n";
  if (d.steps.empty()) return h << "<p>No series stepped.</p>\n";
  h << "<table class=\"steps\"><tr><th>series</th><th>figure</th><th>run</th><th>commit</th>"
       "<th>before</th><th>after</th></tr>\n";
  for (const auto& s : d.steps) {
    h << "<tr><td><a href=\"#" << group_anchor(s.estimator, s.scene) << "\"><code>"
      << text(s.series) << "</code></a></td><td>" << text(s.figure) << "</td><td><code>"
      << text(s.run.run_id) << "</code></td><td><code>" << text(s.run.git_commit.substr(0, 12))
      << "</code></td><td>" << num(s.before) << "</td><td>" << num(s.after) << "</td></tr>\n";
  }
  return h << "</table>\n";
}

}  // namespace

std::string dashboard_html(const Dashboard& d) {
  const bool fail = dashboard_fails(d);
  Html h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << content_security_policy() << "<title>aoeval dashboard</title>\n"
    << "<link rel=\"stylesheet\" href=\"dashboard.css\">\n</head><body>\n"
    << "<header class=\"verdict " << (fail ? Html("fail") : Html("pass")) << "\" id=\"verdict\">";
  // The banner names what regressed: (estimator on scene), each once, in page order.
  std::string names;
  std::vector<std::string> named;
  for (const auto& rep : d.rows) {
    if (rep.verdict != Verdict::regressed) continue;
    const std::string name = rep.estimator + " on " + rep.scene;
    if (std::find(named.begin(), named.end(), name) != named.end()) continue;
    named.push_back(name);
    if (!names.empty()) names += ", ";
    names += name;
  }
  h << "<h1>";
  if (d.regressed > 0) {
    h << "REGRESSED (" << d.regressed << (d.regressed == 1 ? Html(" row") : Html(" rows"))
      << "): " << text(names);
  } else if (fail) {
    h << "CHANGED (" << d.changed << " rows, change_action fail)";
  } else {
    h << "No regression";
  }
  h << "</h1>\n";
  h << "<p>" << d.regressed << " regressed, " << d.warnings << " warnings, " << d.improved
    << " improved";
  if (d.both > 0) h << " (" << d.both << " of them regressed in another key)";
  h << ", " << d.unchanged << " unchanged, " << d.not_compared
    << " not compared; <a href=\"#changed\">" << d.changed << " changed</a>";
  if (d.history_searched)
    h << "; <a href=\"#steps\">" << d.steps.size() << " steps</a> over " << d.history_size
      << " runs";
  h << "</p>\n";
  // Per judged key: how many rows regressed and improved in it.
  if (!d.by_key.empty()) {
    std::string keys;
    for (const auto& [key, counts] : d.by_key)
      keys += (keys.empty() ? "" : "; ") + key + ": " + std::to_string(counts.first) +
              " regressed, " + std::to_string(counts.second) + " improved";
    h << "<p>by key: " << text(keys) << "</p>\n";
  }
  // Timing that could not be judged is said once at the top, with the reason on each row.
  int untimed = 0;
  for (const auto& rep : d.rows)
    for (const auto& c : rep.checks)
      untimed += c.figure == "time_ms_median" && c.verdict == Verdict::not_compared;
  if (untimed > 0) {
    h << "<p>timing not judged on " << untimed
      << " rows (too few repetitions for the rank test, no samples, or another device: see each "
         "row)</p>\n";
  }
  h << "<p>new: " << run_line(d.after_run) << "</p>\n";
  if (d.before_run)
    h << "<p>baseline: " << run_line(*d.before_run) << "</p>\n";
  else
    h << "<p>baseline: none (the first run of this command)</p>\n";
  h << "<p>thresholds: " << text(d.config_source) << "</p></header>\n<main>\n";

  // Summary: every row, in verdict order, linking to its section.
  h << "<h2>Rows</h2>\n<table class=\"summary\"><tr><th>verdict</th><th>estimator</th>"
       "<th>scene</th><th>view</th><th>resolution</th><th>parameters set</th><th>what</th></tr>\n";
  std::map<const RowReport*, size_t> anchors;
  for (size_t i = 0; i < d.rows.size(); ++i) anchors[&d.rows[i]] = i;
  for (const auto& rep : d.rows) {
    std::string what = rep.note;
    for (const auto& c : rep.checks)
      if ((c.verdict == rep.verdict && rep.verdict != Verdict::unchanged) ||
          (c.verdict == Verdict::improved && rep.verdict == Verdict::regressed))
        what += (what.empty() ? "" : "; ") + c.figure + " " + to_string(c.verdict);
    if (!rep.params_change.empty()) what += (what.empty() ? "" : "; ") + rep.params_change;
    if (!rep.code_change.empty())
      what += (what.empty() ? "" : "; ") + std::string("code ") + rep.code_change;
    if (rep.changed) what += (what.empty() ? "" : "; ") + change_phrase(*rep.change);
    if (rep.frames && rep.frames->changed > 0)
      what += (what.empty() ? "" : "; ") + frames_phrase(*rep.frames);
    h << "<tr class=\"" << css_class(rep.verdict) << "\"><td><a href=\"#row-" << anchors[&rep]
      << "\">" << text(to_string(rep.verdict)) << "</a></td><td>" << text(rep.estimator)
      << "</td><td>" << text(rep.scene) << "</td><td>" << text(rep.view) << "</td><td>"
      << text(rep.resolution) << "</td><td>" << text(point_of(rep.run_name)) << "</td><td>"
      << text(what) << "</td></tr>\n";
  }
  h << "</table>\n" << changed_section(d) << steps_section(d);

  // One section per (estimator, scene), in the order their first row appears (failures first).
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<const RowReport*>> members;
  for (const auto& rep : d.rows) {
    const auto key = std::make_pair(rep.estimator, rep.scene);
    if (!members.count(key)) order.push_back(key);
    members[key].push_back(&rep);
  }
  for (const auto& key : order) {
    h << "<section class=\"group\" id=\"" << group_anchor(key.first, key.second) << "\"><h2>"
      << text(key.first) << " on " << text(key.second) << "</h2>\n<div class=\"charts\">";
    for (const auto& g : d.groups)
      if (g.estimator == key.first && g.scene == key.second)
        for (const auto& chart : g.charts)
          h << "<img class=\"chart\" src=\"" << url(chart)
            << "\" loading=\"lazy\" alt=\"history chart\">";
    h << "</div>\n";
    for (const RowReport* rep : members[key]) {
      h << "<article class=\"row " << css_class(rep->verdict) << "\" id=\"row-" << anchors[rep]
        << "\"><h3>" << text(rep->view) << " " << text(rep->resolution) << ": "
        << text(to_string(rep->verdict)) << "</h3>\n<p class=\"note\"><code>" << text(rep->run_name)
        << "</code></p>\n";
      if (!rep->params_change.empty())
        h << "<p>parameters changed: <code>" << text(rep->params_change) << "</code></p>\n";
      if (!rep->code_change.empty())
        h << "<p>code changed: <code>" << text(rep->code_change) << "</code></p>\n";
      if (!rep->note.empty()) h << "<p class=\"note\">" << text(rep->note) << "</p>\n";
      if (!rep->checks.empty()) h << checks_table(*rep);
      h << change_line(*rep) << frames_line(*rep) << images(*rep) << "</article>\n";
    }
    h << "</section>\n";
  }
  h << "</main>\n<script src=\"dashboard.js\"></script>\n</body></html>\n";
  return h.str();
}

}  // namespace aoeval
