// The dashboard page: a verdict banner, the summary table (failures first), then one section per
// (estimator, scene) with its history charts and, per row, the checks and the new | baseline |
// difference images (hovering the new image shows the baseline in its place). Self-contained:
// inline CSS and script, relative image paths, no external URL.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <sstream>

#include "reports/dashboard.h"
#include "reports/html.h"

namespace aoeval {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// The verdict as a CSS class: its name with spaces as dashes ("not compared" -> "not-compared").
std::string css_class(Verdict v) {
  std::string name = to_string(v);
  for (char& c : name)
    if (c == ' ') c = '-';
  return name;
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

std::string run_line(const RunContext& r) {
  return "<code>" + html_escape(r.run_id) + "</code> &middot; commit <code>" +
         html_escape(r.git_commit.substr(0, 12)) + "</code> &middot; " + html_escape(r.started) +
         " &middot; <code>" + html_escape(r.command) + "</code> &middot; " + html_escape(r.machine);
}

const char* kStyle = R"(
body{font-family:"DejaVu Sans",sans-serif;margin:0;background:#f4f4f4;color:#222}
main{padding:0 1.2em 2em}
.verdict{padding:1em 1.2em;color:#fff}
.verdict.fail{background:#b2182b}.verdict.pass{background:#1b7837}
.verdict h1{margin:0 0 .3em;font-size:1.5em}.verdict p{margin:.2em 0}
.verdict code{color:#fff}
table{border-collapse:collapse;background:#fff;margin:.6em 0}
td,th{border:1px solid #ccc;padding:.25em .5em;font-size:.88em;text-align:left;vertical-align:top}
th{background:#eee}
.regressed{background:#fbe3e4}.warning{background:#fff4d6}.improved{background:#e3f4e5}
.unchanged{background:#fff}.not-compared{background:#f0f0f0;color:#666}
section.group{background:#fff;border:1px solid #ddd;margin:1.2em 0;padding:.4em 1em}
section.group h2{font-size:1.2em}
article.row{border-top:1px solid #ddd;padding:.5em 0}
article.row h3{font-size:1em;margin:.3em 0}
.images{display:flex;flex-wrap:wrap;gap:.6em}
figure{margin:0}figcaption{font-size:.8em;color:#555}
.images img{width:340px;max-width:31vw;height:auto;image-rendering:pixelated}
img.swap{cursor:crosshair;outline:2px solid #2166ac}
img.chart{max-width:48%;margin:.2em}
.change{font-size:.88em}article.changed{background:#fff;border:1px solid #e08214;padding:.4em}
.note{color:#555;font-size:.88em}
)";

// Hovering a new image shows its baseline in its place (the browser test checks the swap).
const char* kScript = R"(
document.querySelectorAll('img.swap').forEach(function (img) {
  img.addEventListener('mouseenter', function () { img.src = img.dataset.baseline; });
  img.addEventListener('mouseleave', function () { img.src = img.dataset.new; });
});
)";

std::string checks_table(const RowReport& rep) {
  std::string h =
      "<table class=\"checks\"><tr><th>figure</th><th>baseline</th><th>new</th><th>verdict</th>"
      "<th>why</th></tr>\n";
  for (const auto& c : rep.checks) {
    const bool numbers = c.figure != "status";
    h += "<tr class=\"" + css_class(c.verdict) + "\"><td>" + html_escape(c.figure) + "</td><td>" +
         (numbers ? number(c.before) : "") + "</td><td>" + (numbers ? number(c.after) : "") +
         "</td><td>" + to_string(c.verdict) + "</td><td>" + html_escape(c.detail) + "</td></tr>\n";
  }
  return h + "</table>\n";
}

std::string images(const RowReport& rep) {
  std::string h;
  if (!rep.new_png.empty()) {
    h += "<div class=\"images\">\n<figure><img class=\"swap\" src=\"" + html_escape(rep.new_png) +
         "\" data-new=\"" + html_escape(rep.new_png) + "\" data-baseline=\"" +
         html_escape(rep.baseline_png) +
         "\" loading=\"lazy\" alt=\"new estimate\"><figcaption>new (hover: baseline)"
         "</figcaption></figure>\n";
    h += "<figure><img class=\"baseline\" src=\"" + html_escape(rep.baseline_png) +
         "\" loading=\"lazy\" alt=\"baseline "
         "estimate\"><figcaption>baseline</figcaption></figure>\n";
    if (!rep.diff_png.empty()) {
      h += "<figure><img class=\"difference\" src=\"" + html_escape(rep.diff_png) +
           "\" loading=\"lazy\" alt=\"new minus baseline\"><figcaption>new &minus; baseline (red: "
           "new brighter, "
           "blue: new darker)</figcaption></figure>\n";
    }
    h += "</div>\n";
  }
  if (!rep.image_note.empty()) h += "<p class=\"note\">" + html_escape(rep.image_note) + "</p>\n";
  return h;
}

// One line on the estimate's change against the baseline's (image_change.h).
std::string change_line(const RowReport& rep) {
  if (!rep.change) return "";
  const ImageChange& c = *rep.change;
  char text[320];
  std::snprintf(text, sizeof text,
                "mean_shift %+.4f (limit %.4f), changed pixels %.1f %% (per-pixel threshold %.2g, "
                "noise rule: %s, %zu pixels)",
                c.mean_shift, rep.change_limit, 100.0 * c.changed_pixels, c.pixel_threshold,
                c.noise_rule.c_str(), c.pixels);
  return std::string("<p class=\"change\">") + (rep.changed ? "<b>CHANGED</b>: " : "estimate: ") +
         html_escape((rep.changed ? change_phrase(c) + "; " : std::string()) + text) + "</p>\n";
}

std::string group_anchor(const std::string& estimator, const std::string& scene) {
  std::string a = "group-" + estimator + "-" + scene;
  for (char& ch : a)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-') ch = '-';
  return a;
}

// The "Changed" section: every changed row with its parameters, its change and its images.
std::string changed_section(const Dashboard& d) {
  if (d.changed == 0) return "";
  std::string h = "<h2 id=\"changed\">Changed (" + std::to_string(d.changed) +
                  ")</h2>\n<p class=\"note\">The estimate itself moved against the baseline's "
                  "(mean of new &minus; baseline AO beyond change_mean_shift and its noise), "
                  "whatever its error did.</p>\n";
  for (const auto& rep : d.rows) {
    if (!rep.changed) continue;
    h += "<article class=\"row changed\"><h3>" + html_escape(rep.estimator) + " <code>" +
         html_escape(rep.params_text) + "</code> on " + html_escape(rep.scene) + ", " +
         html_escape(rep.view) + " " + html_escape(rep.resolution) + ": " +
         html_escape(change_phrase(*rep.change)) + (rep.change_fails ? " (fails)" : " (warns)") +
         "</h3>\n" + change_line(rep) + images(rep) + "</article>\n";
  }
  return h;
}

// The "Steps" section of --history: one line per step, linking to its group's charts.
std::string steps_section(const Dashboard& d) {
  if (!d.history_searched) return "";
  std::string h = "<h2 id=\"steps\">Steps over the last " + std::to_string(d.history_size) +
                  " runs (" + std::to_string(d.steps.size()) + ")</h2>\n";
  if (d.steps.empty()) return h + "<p>No series stepped.</p>\n";
  h += "<table class=\"steps\"><tr><th>series</th><th>figure</th><th>run</th><th>commit</th>"
       "<th>before</th><th>after</th></tr>\n";
  for (const auto& s : d.steps) {
    h += "<tr><td><a href=\"#" + group_anchor(s.estimator, s.scene) + "\"><code>" +
         html_escape(s.series) + "</code></a></td><td>" + html_escape(s.figure) +
         "</td><td><code>" + html_escape(s.run.run_id) + "</code></td><td><code>" +
         html_escape(s.run.git_commit.substr(0, 12)) + "</code></td><td>" + number(s.before) +
         "</td><td>" + number(s.after) + "</td></tr>\n";
  }
  return h + "</table>\n";
}

}  // namespace

std::string dashboard_html(const Dashboard& d) {
  const bool fail = dashboard_fails(d);
  std::string h =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      "<title>aoeval dashboard</title>\n<style>";
  h += kStyle;
  h += "</style></head><body>\n";
  h += std::string("<header class=\"verdict ") + (fail ? "fail" : "pass") + "\" id=\"verdict\">";
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
  h += "<h1>" +
       (d.regressed > 0 ? "REGRESSED (" + std::to_string(d.regressed) +
                              (d.regressed == 1 ? " row" : " rows") + "): " + html_escape(names)
        : fail ? "CHANGED (" + std::to_string(d.changed) + " rows, change_action fail)"
               : std::string("No regression")) +
       "</h1>\n";
  h += "<p>" + std::to_string(d.regressed) + " regressed, " + std::to_string(d.warnings) +
       " warnings, " + std::to_string(d.improved) + " improved" +
       (d.both > 0 ? " (" + std::to_string(d.both) + " of them regressed in another key)"
                   : std::string()) +
       ", " + std::to_string(d.unchanged) + " unchanged, " + std::to_string(d.not_compared) +
       " not compared; <a href=\"#changed\">" + std::to_string(d.changed) + " changed</a>" +
       (d.history_searched ? "; <a href=\"#steps\">" + std::to_string(d.steps.size()) +
                                 " steps</a> over " + std::to_string(d.history_size) + " runs"
                           : std::string()) +
       "</p>\n";
  // Per judged key: how many rows regressed and improved in it.
  if (!d.by_key.empty()) {
    std::string keys;
    for (const auto& [key, counts] : d.by_key)
      keys += (keys.empty() ? "" : "; ") + key + ": " + std::to_string(counts.first) +
              " regressed, " + std::to_string(counts.second) + " improved";
    h += "<p>by key: " + html_escape(keys) + "</p>\n";
  }
  // Timing that could not be judged is said once at the top, with the reason on each row.
  int untimed = 0;
  for (const auto& rep : d.rows)
    for (const auto& c : rep.checks)
      untimed += c.figure == "time_ms_median" && c.verdict == Verdict::not_compared;
  if (untimed > 0) {
    h += "<p>timing not judged on " + std::to_string(untimed) +
         " rows (too few repetitions for the rank test, no samples, or another device: see each "
         "row)</p>\n";
  }
  h += "<p>new: " + run_line(d.after_run) + "</p>\n";
  h += d.before_run ? "<p>baseline: " + run_line(*d.before_run) + "</p>\n"
                    : std::string("<p>baseline: none (the first run of this command)</p>\n");
  h += "<p>thresholds: " + html_escape(d.config_source) + "</p></header>\n<main>\n";

  // Summary: every row, in verdict order, linking to its section.
  h += "<h2>Rows</h2>\n<table class=\"summary\"><tr><th>verdict</th><th>estimator</th>"
       "<th>scene</th><th>view</th><th>resolution</th><th>parameters set</th><th>what</th></tr>\n";
  std::map<const RowReport*, std::string> anchors;
  for (size_t i = 0; i < d.rows.size(); ++i) anchors[&d.rows[i]] = "row-" + std::to_string(i);
  for (const auto& rep : d.rows) {
    std::string what = rep.note;
    for (const auto& c : rep.checks)
      if ((c.verdict == rep.verdict && rep.verdict != Verdict::unchanged) ||
          (c.verdict == Verdict::improved && rep.verdict == Verdict::regressed))
        what += (what.empty() ? "" : "; ") + c.figure + " " + to_string(c.verdict);
    if (!rep.params_change.empty()) what += (what.empty() ? "" : "; ") + rep.params_change;
    if (rep.changed) what += (what.empty() ? "" : "; ") + change_phrase(*rep.change);
    h += "<tr class=\"" + css_class(rep.verdict) + "\"><td><a href=\"#" + anchors[&rep] + "\">" +
         to_string(rep.verdict) + "</a></td><td>" + html_escape(rep.estimator) + "</td><td>" +
         html_escape(rep.scene) + "</td><td>" + html_escape(rep.view) + "</td><td>" +
         html_escape(rep.resolution) + "</td><td>" + html_escape(point_of(rep.run_name)) +
         "</td><td>" + html_escape(what) + "</td></tr>\n";
  }
  h += "</table>\n";
  h += changed_section(d);
  h += steps_section(d);

  // One section per (estimator, scene), in the order their first row appears (failures first).
  std::vector<std::pair<std::string, std::string>> order;
  std::map<std::pair<std::string, std::string>, std::vector<const RowReport*>> members;
  for (const auto& rep : d.rows) {
    const auto key = std::make_pair(rep.estimator, rep.scene);
    if (!members.count(key)) order.push_back(key);
    members[key].push_back(&rep);
  }
  for (const auto& key : order) {
    h += "<section class=\"group\" id=\"" + group_anchor(key.first, key.second) + "\"><h2>" +
         html_escape(key.first) + " on " + html_escape(key.second) +
         "</h2>\n<div class=\"charts\">";
    for (const auto& g : d.groups)
      if (g.estimator == key.first && g.scene == key.second)
        for (const auto& chart : g.charts)
          h += "<img class=\"chart\" src=\"" + html_escape(chart) +
               "\" loading=\"lazy\" alt=\"history chart\">";
    h += "</div>\n";
    for (const RowReport* rep : members[key]) {
      h += "<article class=\"row " + css_class(rep->verdict) + "\" id=\"" + anchors[rep] +
           "\"><h3>" + html_escape(rep->view) + " " + html_escape(rep->resolution) + ": " +
           to_string(rep->verdict) + "</h3>\n<p class=\"note\"><code>" +
           html_escape(rep->run_name) + "</code></p>\n";
      if (!rep->params_change.empty())
        h += "<p>parameters changed: <code>" + html_escape(rep->params_change) + "</code></p>\n";
      if (!rep->code_change.empty())
        h += "<p>code changed: <code>" + html_escape(rep->code_change) + "</code></p>\n";
      if (!rep->note.empty()) h += "<p class=\"note\">" + html_escape(rep->note) + "</p>\n";
      if (!rep->checks.empty()) h += checks_table(*rep);
      h += change_line(*rep);
      h += images(*rep);
      h += "</article>\n";
    }
    h += "</section>\n";
  }
  h += "</main>\n<script>";
  h += kScript;
  h += "</script>\n</body></html>\n";
  return h;
}

}  // namespace aoeval
