// `aoeval sweep SPEC.json [--out DIR] [--resume] [--shard I/N] [--db FILE]` (CONTRACT §5).
#include "errors.h"
#include "harness/plugins/plugin_options.h"
#include "harness/sweep/sweep_runner.h"
#include "harness/cli/commands.h"

namespace aoeval {

void add_sweep_command(CLI::App& app) {
  static SweepOptions o;
  auto* cmd = app.add_subcommand("sweep", "a parameter sweep (CONTRACT §5)");
  cmd->add_option("SPEC", o.spec_path, "sweep specification (JSON)")->required();
  cmd->add_option("--out", o.out_dir, "output folder (default: out/<spec name>)");
  cmd->add_flag("--resume", o.resume, "continue an interrupted sweep in the same --out");
  cmd->add_option("--shard", o.shard, "run shard I of N (0-based), e.g. 0/4");
  cmd->add_option("--db", o.database, "SQLite results store");
  cmd->add_option("--max-points", o.max_points,
                  "refuse sweeps with more points than this (a guard against typos in ranges)")
      ->check(CLI::Range(size_t{1}, size_t{1} << 40));
  add_plugins_option(cmd);
  cmd->callback([] {
    const int status = run_sweep(o);
    if (status != 0) throw ExitStatus{status};
  });
}

}  // namespace aoeval
