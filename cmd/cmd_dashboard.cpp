// `aoeval dashboard [--db FILE] [--baseline RUN] [--out DIR]` (CONTRACT §2): the newest run of the
// results history against a baseline under noise-aware rules (reports/regression.h); writes
// <out>/index.html and exits 1 when a tracked figure regressed past its threshold, 0 otherwise,
// so it can gate CI. Extra options: --run RUN (judge another run than the newest), --config FILE
// (thresholds; default reports/dashboard.json), --no-charts, --history N (the last N runs' steps,
// CONTRACT §12), --plugins DIR (so console lines know a plug-in's defaults).
#include <cstdio>

#include "base/errors.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "estimators/registry.h"
#include "reports/dashboard.h"

namespace aoeval {

void add_dashboard_command(CLI::App& app) {
  static DashboardOptions o;
  static bool no_charts = false;
  auto* cmd = app.add_subcommand(
      "dashboard", "regression dashboard: the newest run against a baseline; exit 1 if regressed");
  cmd->add_option("--db", o.database, "SQLite results store");
  cmd->add_option("--baseline", o.baseline_run,
                  "baseline run id (default: the previous run of the same command)");
  cmd->add_option("--run", o.new_run, "run id to judge (default: the newest run with rows)");
  cmd->add_option("--out", o.out_dir, "output folder of the page");
  cmd->add_option("--config", o.config_path,
                  "thresholds file (default: reports/dashboard.json of the source tree)");
  cmd->add_flag("--no-charts", no_charts, "skip the history charts (matplotlib; seconds)");
  cmd->add_option("--history", o.history_steps,
                  "find the steps of every row's rmse_excess, mean AO and median time over the "
                  "last N runs of the suite or sweep")
      ->check(CLI::Range(2, 100000));
  add_plugins_option(cmd);
  cmd->callback([] {
    o.charts = !no_charts;
    // The registry's defaults name the parameters that differ from them first in console lines;
    // a broken plug-in folder in $AOEVAL_PLUGINS only costs that ordering, not the verdict.
    try {
      for (const auto& e : estimator_registry())
        o.estimator_defaults[e.name] = default_params(e).json();
    } catch (const InputError& e) {
      std::fprintf(stderr, "dashboard: estimator defaults unavailable (%s)\n", e.what());
    }
    const Dashboard d = build_dashboard(o);
    for (const auto& line : console_lines(d)) std::printf("%s\n", line.c_str());
    std::printf(
        "dashboard: %d regressed, %d warnings, %d improved (%d both regressed and improved), "
        "%d unchanged, %d not compared, %d changed",
        d.regressed, d.warnings, d.improved, d.both, d.unchanged, d.not_compared, d.changed);
    for (const auto& [key, counts] : d.by_key)
      std::printf("; %s %d regressed %d improved", key.c_str(), counts.first, counts.second);
    if (d.history_searched) std::printf(", %zu steps in %zu runs", d.steps.size(), d.history_size);
    if (d.before_run) {
      std::printf(" (%s against baseline %s)\n", d.after_run.run_id.c_str(),
                  d.before_run->run_id.c_str());
    } else {
      std::printf(" (%s: no earlier run of \"%s\" to compare with)\n", d.after_run.run_id.c_str(),
                  d.after_run.command.c_str());
    }
    std::printf("%s\n", d.page.c_str());
    std::fflush(stdout);
    if (dashboard_fails(d)) throw ExitStatus{1};
  });
}

}  // namespace aoeval
