// `aoeval dashboard`: choosing the runs, pairing their rows, judging each pair (see dashboard.h).
#include "reports/dashboard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "base/errors.h"
#include "base/param_text.h"
#include "reports/page_assets.h"
#include "reports/regression_config.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

using RunRows = std::pair<RunContext, std::vector<ResultRow>>;

// The command without its `--set E:K=V` overrides: a run made with a parameter changed is still a
// run of the same suite, judged against that suite's previous run and drawn in its history.
std::string command_family(const std::string& command) {
  std::string out, word;
  bool skip_next = false;
  std::istringstream in(command);
  while (in >> word) {
    if (skip_next) {
      skip_next = false;
    } else if (word == "--set") {
      skip_next = true;
    } else if (word.rfind("--set=", 0) != 0) {
      if (!out.empty()) out += ' ';
      out += word;
    }
  }
  return out;
}

std::string loose_key(const ResultRow& r) {
  return r.estimator + "|" + r.scene + "|" + r.view + "|" + std::to_string(r.width) + "x" +
         std::to_string(r.height);
}

// "glsl-plugin:my-ao 3f2a91c -> 8b0d4e2" when the rows' estimator_version differ (both known):
// the estimator's own code changed (a plug-in's shader or script, a built-in's folder).
std::string estimator_code_change(const ResultRow& before, const ResultRow& after) {
  const std::string& b = before.estimator_version;
  const std::string& a = after.estimator_version;
  if (b.empty() || a.empty() || b == a) return "";
  const auto split = [](const std::string& v) {
    const size_t colon = v.find(':');
    const std::string kind = colon == std::string::npos ? "" : v.substr(0, colon);
    return std::pair{kind == "built-in" || kind.empty() ? kind : kind + "-plugin",
                     v.substr(colon == std::string::npos ? 0 : colon + 1, 7)};
  };
  const auto [kind, from] = split(b);
  const std::string to = split(a).second;
  return (kind.empty() ? "" : kind + ":") + after.estimator + " " + from + " -> " + to;
}

// What changed in the code between the two rows: the estimator's own code, aoeval's version and
// the git commit.
std::string code_change(const ResultRow& before, const ResultRow& after) {
  std::string out = estimator_code_change(before, after);
  if (before.aoeval_version != after.aoeval_version)
    out += (out.empty() ? "" : ", ") + std::string("aoeval ") + before.aoeval_version + " -> " +
           after.aoeval_version;
  if (before.git_commit != after.git_commit)
    out += (out.empty() ? "" : ", ") + std::string("commit ") + before.git_commit.substr(0, 12) +
           " -> " + after.git_commit.substr(0, 12);
  return out;
}

int severity_rank(Verdict v) {
  switch (v) {
    case Verdict::regressed:
      return 0;
    case Verdict::warning:
      return 1;
    case Verdict::improved:
      return 2;
    case Verdict::unchanged:
      return 3;
    case Verdict::not_compared:
      return 4;
  }
  return 5;
}

RowReport report_for(const ResultRow* before, const ResultRow* after) {
  const ResultRow& r = after ? *after : *before;
  RowReport rep;
  rep.estimator = r.estimator;
  rep.scene = r.scene;
  rep.view = r.view;
  rep.resolution = std::to_string(r.width) + "x" + std::to_string(r.height);
  rep.run_name = r.run_name;
  if (before) rep.before = *before;
  if (after) rep.after = *after;
  if (before && after) {
    rep.params_change = params_change(before->params, after->params);
    rep.code_change = code_change(*before, *after);
  }
  return rep;
}

// Pairs the rows of the two runs (dashboard.h: by run_name, then by the loose key, in row order).
std::vector<RowReport> pair_rows(const std::vector<ResultRow>& before,
                                 const std::vector<ResultRow>& after) {
  std::map<std::string, const ResultRow*> before_by_name;
  for (const auto& r : before) before_by_name[r.run_name] = &r;
  std::vector<RowReport> out;
  std::vector<const ResultRow*> after_left;
  std::map<std::string, bool> before_used;
  for (const auto& r : after) {
    const auto it = before_by_name.find(r.run_name);
    if (it == before_by_name.end()) {
      after_left.push_back(&r);
    } else {
      out.push_back(report_for(it->second, &r));
      before_used[r.run_name] = true;
    }
  }
  std::map<std::string, std::vector<const ResultRow*>> before_left, after_loose;
  for (const auto& r : before)
    if (!before_used.count(r.run_name)) before_left[loose_key(r)].push_back(&r);
  for (const ResultRow* r : after_left) after_loose[loose_key(*r)].push_back(r);
  for (auto& [key, rows] : after_loose) {
    auto it = before_left.find(key);
    if (it != before_left.end() && it->second.size() == rows.size()) {
      for (size_t k = 0; k < rows.size(); ++k) {
        out.push_back(report_for(it->second[k], rows[k]));
      }
      before_left.erase(it);
    } else {
      for (const ResultRow* r : rows) out.push_back(report_for(nullptr, r));
    }
  }
  for (const auto& [key, rows] : before_left)
    for (const ResultRow* r : rows) out.push_back(report_for(r, nullptr));
  return out;
}

// An ok row's estimate image, read and checked: a missing or unreadable file, an AO outside
// [0, 1] on a covered pixel (NaN, infinite, negative: read_ao_exr names the pixel) or a size other
// than the row's is damaged input (exit 2 naming the file), never a row the change check silently
// leaves out (issue 48).
AoPlanes read_estimate(const std::string& exr, const ResultRow& row) {
  AoPlanes p;
  try {
    p = read_planes(exr);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (the estimate of row " + row.run_name + ")");
  }
  if (p.w != row.width || p.h != row.height)
    throw InputError(exr + ": estimate image is " + std::to_string(p.w) + "x" +
                     std::to_string(p.h) + ", its row " + row.run_name + " says " +
                     std::to_string(row.width) + "x" + std::to_string(row.height));
  return p;
}

// Reads both estimates (read_estimate: damaged ones are an InputError), measures the change
// (image_change.h) and writes the row's images.
void measure_change(RowReport& rep, const std::string& before_exr, const std::string& after_exr,
                    const Thresholds& t, const std::string& out_dir, std::optional<double>* delta) {
  const AoPlanes b = read_estimate(before_exr, *rep.before);
  const AoPlanes a = read_estimate(after_exr, *rep.after);
  *delta = write_row_images(rep, b, a, out_dir);
  const auto seed_b = rep.before->params.find("seed"), seed_a = rep.after->params.find("seed");
  const bool seeds_differ =
      seed_b != rep.before->params.end() && seed_a != rep.after->params.end() && *seed_b != *seed_a;
  try {
    rep.change = compare_estimates(b, a, seeds_differ);
  } catch (const std::invalid_argument& e) {
    rep.image_note = std::string("no change measured: ") + e.what();
    return;
  }
  rep.change_limit = change_threshold(*rep.change, t.change_mean_shift);
  rep.changed = std::abs(rep.change->mean_shift) > rep.change_limit;
  rep.change_fails = t.change_fails;
}

void judge(RowReport& rep, const Thresholds& t, std::optional<double> delta_rms) {
  const bool before_ok = rep.before && rep.before->status == "ok";
  const bool after_ok = rep.after && rep.after->status == "ok";
  if (before_ok && after_ok) {
    rep.checks = compare_rows(
        *rep.before, *rep.after, t, delta_rms,
        rep.change && std::isfinite(rep.change->sigma_mean) ? rep.change->sigma_mean : 0.0);
  } else if (before_ok) {
    rep.checks = {missing_check(rep.after ? &*rep.after : nullptr, t)};
  } else if (!rep.before) {
    rep.note = "new row: no baseline to compare with";
  } else if (after_ok) {
    rep.note = "baseline row was \"" + rep.before->status + "\": nothing to compare with";
  } else if (rep.after) {
    rep.note = "not run in either: \"" + rep.after->status + "\"";
  } else {
    rep.note = "baseline row was \"" + rep.before->status + "\", absent now";
  }
  rep.verdict = worst(rep.checks);
}

const RunContext* find_run(const std::vector<RunContext>& runs, const std::string& id,
                           const char* option) {
  for (const auto& r : runs)
    if (r.run_id == id) return &r;
  throw InputError(std::string(option) + " " + id + ": no such run in the database");
}

}  // namespace

Dashboard build_dashboard(const DashboardOptions& o) {
  const RegressionConfig config = RegressionConfig::load(
      o.config_path.empty() ? default_regression_config_path() : o.config_path);
  // Read-only: the dashboard judges someone's history and must never convert it to WAL or add
  // tables; a missing, corrupt or foreign file is bad input (exit 2), never "regressed" (exit 1).
  SqliteStore store(o.database, SqliteStore::Mode::read_only);
  std::vector<RunContext> runs;
  std::map<std::string, std::vector<ResultRow>> rows_of;
  try {
    runs = store.runs();
    for (const auto& r : runs) rows_of[r.run_id] = store.rows_of_run(r.run_id);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("--db " + o.database + ": cannot read the results (" + e.what() + ")");
  }

  const RunContext* after = nullptr;
  if (!o.new_run.empty()) {
    after = find_run(runs, o.new_run, "--run");
  } else {
    for (auto it = runs.rbegin(); it != runs.rend() && !after; ++it)
      if (!rows_of[it->run_id].empty()) after = &*it;
    if (!after) throw InputError("--db " + o.database + ": holds no results rows");
  }
  const RunContext* before = nullptr;
  if (!o.baseline_run.empty()) {
    before = find_run(runs, o.baseline_run, "--baseline");
    if (before->run_id == after->run_id)
      throw InputError("--baseline " + o.baseline_run + ": is the run being judged");
  } else {
    for (const auto& r : runs) {
      if (r.run_id == after->run_id) break;
      if (command_family(r.command) == command_family(after->command) && !rows_of[r.run_id].empty())
        before = &r;
    }
  }

  Dashboard d;
  d.after_run = *after;
  d.config_source = config.source();
  const std::vector<ResultRow> no_rows;
  if (before) d.before_run = *before;
  d.rows = pair_rows(before ? rows_of[before->run_id] : no_rows, rows_of[after->run_id]);
  // Every compared estimate image is checked before anything is written: a damaged one exits 2
  // with no page and no images behind.
  for (const RowReport& rep : d.rows) {
    if (!rep.before || !rep.after || rep.before->status != "ok" || rep.after->status != "ok")
      continue;
    const std::string b = estimate_path(*rep.before, *before);
    const std::string a = estimate_path(*rep.after, *after);
    if (b.empty() || a.empty()) continue;
    read_estimate(b, *rep.before);
    read_estimate(a, *rep.after);
  }
  fs::create_directories(o.out_dir);
  for (RowReport& rep : d.rows) {
    const ResultRow& r = rep.after ? *rep.after : *rep.before;
    const auto defaults = o.estimator_defaults.find(r.estimator);
    rep.params_text = params_text(
        r.params, r.run_name, defaults == o.estimator_defaults.end() ? nullptr : &defaults->second);
    const Thresholds t = config.thresholds(rep.estimator, rep.scene);
    std::optional<double> delta;
    if (rep.before && rep.after && rep.before->status == "ok" && rep.after->status == "ok") {
      const std::string b = estimate_path(*rep.before, *before);
      const std::string a = estimate_path(*rep.after, *after);
      if (b.empty() || a.empty()) {
        rep.image_note = "estimate images were not kept (no estimate_file or output folder)";
      } else {
        measure_change(rep, b, a, t, o.out_dir, &delta);
      }
    }
    judge(rep, t, delta);
    if (rep.before && rep.after && rep.before->status == "ok" && rep.after->status == "ok") {
      rep.before_frames = store.frames_of(before->run_id, rep.before->run_name);
      rep.after_frames = store.frames_of(after->run_id, rep.after->run_name);
      rep.frames = frame_change(rep.before_frames, rep.after_frames, t,
                                same_reference(*rep.before, *rep.after));
    }
  }
  std::stable_sort(d.rows.begin(), d.rows.end(), [](const RowReport& x, const RowReport& y) {
    if (severity_rank(x.verdict) != severity_rank(y.verdict))
      return severity_rank(x.verdict) < severity_rank(y.verdict);
    return std::tie(x.estimator, x.scene, x.view) < std::tie(y.estimator, y.scene, y.view);
  });
  for (const auto& rep : d.rows) {
    d.changed += rep.changed;
    d.changes_failing += rep.changed && rep.change_fails;
    int* counter = rep.verdict == Verdict::regressed   ? &d.regressed
                   : rep.verdict == Verdict::warning   ? &d.warnings
                   : rep.verdict == Verdict::improved  ? &d.improved
                   : rep.verdict == Verdict::unchanged ? &d.unchanged
                                                       : &d.not_compared;
    ++*counter;
    bool improved = false;
    for (const Check& c : rep.checks) {
      if (c.verdict == Verdict::regressed) ++d.by_key[c.figure].first;
      if (c.verdict == Verdict::improved) ++d.by_key[c.figure].second;
      improved = improved || c.verdict == Verdict::improved;
    }
    if (improved && rep.verdict != Verdict::improved) {
      ++d.improved;  // a key improved beside one that regressed (or warned): counted as both
      ++d.both;
    }
  }

  // History: the runs of the same command up to the new one, the newest history_runs of them.
  std::vector<RunRows> history;
  for (const auto& r : runs) {
    if (command_family(r.command) == command_family(after->command) && !rows_of[r.run_id].empty())
      history.emplace_back(r, rows_of[r.run_id]);
    if (r.run_id == after->run_id) break;
  }
  const size_t keep = o.history_steps > 0 ? o.history_steps : o.history_runs;
  if (history.size() > keep)
    history.erase(history.begin(), history.end() - static_cast<long>(keep));
  if (o.history_steps > 0) {
    d.history_searched = true;
    d.history_size = history.size();
    find_steps(d, history, config);
  }
  if (o.charts) d.groups = write_history_charts(d, history, o.out_dir);

  d.page = (fs::path(o.out_dir) / "index.html").string();
  write_page_asset(o.out_dir, "dashboard.css");
  write_page_asset(o.out_dir, "dashboard.js");
  write_text(d.page, dashboard_html(d));
  return d;
}

std::string params_change(const nlohmann::json& before, const nlohmann::json& after) {
  std::string out;
  auto add = [&](const std::string& key, const std::string& b, const std::string& a) {
    if (!out.empty()) out += ", ";
    out += key + " " + b + " -> " + a;
  };
  if (!before.is_object() || !after.is_object()) return out;
  for (const auto& [key, value] : after.items()) {
    if (key == "derived") continue;
    if (!before.contains(key)) {
      add(key, "(none)", format_param_value(value));
    } else if (before[key] != value) {
      add(key, format_param_value(before[key]), format_param_value(value));
    }
  }
  for (const auto& [key, value] : before.items())
    if (key != "derived" && !after.contains(key)) add(key, format_param_value(value), "(none)");
  return out;
}

std::string params_text(const nlohmann::json& params, const std::string& run_name,
                        const nlohmann::json* defaults) {
  std::string first, rest;
  if (!params.is_object()) return "-";
  for (const auto& [key, value] : params.items()) {
    if (key == "derived") continue;
    const bool differs =
        defaults ? !defaults->contains(key) || (*defaults)[key] != value
                 : run_name.find("/" + key + ":") != std::string::npos;  // set explicitly
    std::string& to = differs ? first : rest;
    if (!to.empty()) to += ',';
    to += key + "=" + format_param_value(value);
  }
  const std::string all = first + (!first.empty() && !rest.empty() ? "," : "") + rest;
  return all.empty() ? "-" : all;
}

bool dashboard_fails(const Dashboard& d) {
  return d.regressed > 0 || d.changes_failing > 0;
}

std::string frames_phrase(const FrameChange& f) {
  if (f.changed == 0)
    return f.figure + " unchanged on all " + std::to_string(f.compared) + " frames compared";
  char most[160];
  std::snprintf(most, sizeof most, "; most at frame %d: %.4g -> %.4g)", f.largest_frame,
                f.largest_before, f.largest_after);
  return f.figure + " changed on frame" + (f.changed > 1 ? "s " : " ") + spans_text(f.spans) +
         " (" + std::to_string(f.changed) + " of " + std::to_string(f.compared) + " frames" + most;
}

std::vector<std::string> console_lines(const Dashboard& d) {
  std::vector<std::string> out;
  auto row_name = [](const RowReport& rep) {
    return rep.estimator + " " + rep.params_text + " scene " + rep.scene + " view " + rep.view +
           " " + rep.resolution + ":";
  };
  for (const auto& rep : d.rows) {
    if (rep.verdict != Verdict::regressed && rep.verdict != Verdict::warning &&
        rep.verdict != Verdict::improved)
      continue;
    const char* word = rep.verdict == Verdict::regressed ? "REGRESSED "
                       : rep.verdict == Verdict::warning ? "WARNING "
                                                         : "IMPROVED ";
    std::string line = word + row_name(rep);
    auto add_checks = [&](bool want_improved) {
      for (const auto& c : rep.checks) {
        const bool bad = c.verdict == Verdict::regressed || c.verdict == Verdict::warning;
        if (want_improved ? c.verdict != Verdict::improved : !bad) continue;
        char numbers[200];
        std::snprintf(numbers, sizeof numbers, " %s %.4g -> %.4g (threshold %.3g);",
                      c.figure.c_str(), c.before, c.after, c.threshold);
        line += c.figure == "status" ? " " + c.detail + ";" : std::string(numbers);
      }
    };
    add_checks(rep.verdict == Verdict::improved);
    if (rep.verdict != Verdict::improved &&
        std::any_of(rep.checks.begin(), rep.checks.end(),
                    [](const Check& c) { return c.verdict == Verdict::improved; })) {
      line += " also IMPROVED:";
      add_checks(true);
    }
    if (!rep.params_change.empty()) line += " parameters changed: " + rep.params_change + ";";
    if (!rep.code_change.empty()) line += " code changed: " + rep.code_change + ";";
    if (line.back() == ';') line.pop_back();
    out.push_back(line);
  }
  for (const auto& rep : d.rows)
    if (rep.changed)
      out.push_back(
          "CHANGED " + row_name(rep) + " " + change_phrase(*rep.change) +
          (rep.params_change.empty() ? "" : "; parameters changed: " + rep.params_change) +
          (rep.code_change.empty() ? "" : "; code changed: " + rep.code_change));
  for (const auto& rep : d.rows)
    if (rep.frames && rep.frames->changed > 0)
      out.push_back("FRAMES " + row_name(rep) + " " + frames_phrase(*rep.frames));
  for (const auto& s : d.steps) {
    char numbers[200];
    std::snprintf(numbers, sizeof numbers, ": %s %.4f -> %.4f", s.figure.c_str(), s.before,
                  s.after);
    out.push_back("STEP " + s.series + " at run " + s.run.run_id + " (" +
                  s.run.git_commit.substr(0, 12) + ")" + numbers);
  }
  return out;
}

}  // namespace aoeval
