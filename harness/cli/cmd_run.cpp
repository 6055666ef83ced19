// `aoeval run [--suite default|quick|paper|FILE.json] [--out DIR] [--db FILE]
//  [--set ESTIMATOR:KEY=VALUE]...`: the main job (CONTRACT §2). References and every estimator over
// the suite's scenes, metrics, error maps, timing tables and the HTML report, whose path is the
// last line on stdout.
#include <cstdio>

#include "harness/cli/commands.h"
#include "harness/sweep/suite_runner.h"

namespace aoeval {

void add_run_command(CLI::App& app) {
  static SuiteRunOptions o;
  auto* cmd = app.add_subcommand("run", "run a suite and write its HTML report");
  cmd->add_option("--suite", o.suite,
                  "quick, default or paper (harness/suites/NAME.json), or a suite file: a list of "
                  "sweep specifications (CONTRACT §5)");
  cmd->add_option("--out", o.out_dir, "output folder (default: out/SUITE)");
  cmd->add_option("--db", o.database, "SQLite results store");
  cmd->add_option(
      "--set", o.sets,
      "ESTIMATOR:KEY=VALUE: replaces KEY's value in every run of ESTIMATOR (repeatable)");
  cmd->callback([] { std::printf("%s\n", run_suite(o).c_str()); });
}

}  // namespace aoeval
