// `aoeval tune SPEC.json [--out DIR] [--db FILE]` (CONTRACT §8; harness/tune/tune_runner.h).
#include "base/errors.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "harness/tune/tune_runner.h"

namespace aoeval {

void add_tune_command(CLI::App& app) {
  static TuneOptions o;
  auto* cmd = app.add_subcommand(
      "tune", "search an estimator's parameters for the least error under a time budget (§8)");
  cmd->add_option("SPEC", o.spec_path, "tune specification (JSON)")->required();
  cmd->add_option("--out", o.out_dir,
                  "output folder (default: out/<spec name>); running the same command again "
                  "continues an interrupted tune there");
  cmd->add_option("--db", o.database, "SQLite results store");
  add_plugins_option(cmd);
  cmd->callback([] {
    const int status = run_tune(o);
    if (status != 0) throw ExitStatus{status};
  });
}

}  // namespace aoeval
