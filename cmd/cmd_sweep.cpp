// `aoeval sweep SPEC.json [--out DIR] [--resume] [--shard I/N] [--db FILE]` (CONTRACT §5): the
// rows, then (unsharded) the page a suite gets, whose path is the last line on stdout.
#include <cstdio>
#include <filesystem>

#include "base/errors.h"
#include "cmd/cluster_options.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "harness/sweep/sweep_runner.h"
#include "reports/run_pages.h"

namespace aoeval {

void add_sweep_command(CLI::App& app) {
  static SweepOptions o;
  auto* cmd = app.add_subcommand("sweep", "a parameter sweep (CONTRACT §5)");
  cmd->add_option("SPEC", o.spec_path, "sweep specification (JSON)")->required();
  cmd->add_option("--out", o.out_dir, "output folder (default: out/<spec name>)");
  cmd->add_flag("--resume", o.resume, "continue an interrupted sweep in the same --out");
  cmd->add_option("--shard", o.shard,
                  "run shard I of N (0-based), e.g. 0/4; auto: SLURM_ARRAY_TASK_ID of "
                  "SLURM_ARRAY_TASK_COUNT");
  cmd->add_option("--shard-plan", o.shard_plan,
                  "with --shard: the cost-balanced plan's shard (written by --slurm)");
  cmd->add_option("--db", o.database, "SQLite results store");
  cmd->add_option("--max-points", o.max_points,
                  "refuse sweeps with more points than this (a guard against typos in ranges)")
      ->check(CLI::Range(size_t{1}, size_t{1} << 40));
  add_plugins_option(cmd);
  static ClusterOptions c;
  add_cluster_options(cmd, c);
  cmd->callback([cmd] {
    check_cluster_options(cmd, c);
    if (c.slurm || c.references_only) {
      const SweepSpec spec = load_sweep_spec(o.spec_path);
      const std::vector<SweepPoint> points = expand_sweep(spec, o.max_points);
      std::vector<StagePoint> stage;
      for (const auto& p : points) stage.push_back({&p, &spec});
      if (c.references_only) return run_reference_stage(stage, o.shard);
      SlurmSubmission s;
      s.command = "sweep";
      s.input_args = {std::filesystem::absolute(o.spec_path).string(), "--max-points",
                      std::to_string(o.max_points)};
      add_plugin_args(cmd, s.input_args);
      s.name = spec.name;
      s.out = o.out_dir;
      s.database = o.database;
      s.resume = o.resume;
      s.points = stage;
      s.cluster = c;
      return submit_to_slurm(s);
    }
    std::string out, page;
    // The sweep's page, as a suite's (its Pareto fronts featured); a shard's page is the merge's.
    if (o.shard.empty()) o.pages = write_run_pages;
    const int status = run_sweep(o, &out, &page);
    if (status != 0) throw ExitStatus{status};
    std::printf("%s\n", page.empty() ? (std::filesystem::path(out) / "results.csv").string().c_str()
                                     : page.c_str());
  });
}

}  // namespace aoeval
