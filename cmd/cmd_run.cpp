// `aoeval run [--suite default|quick|paper|FILE.json] [--out DIR] [--db FILE]
//  [--set ESTIMATOR:KEY=VALUE]...`: the main job (CONTRACT §2). References and every estimator over
// the suite's scenes, metrics, error maps, timing tables and the HTML report, whose path is the
// last line on stdout.
#include <cstdio>
#include <filesystem>

#include "base/errors.h"
#include "cmd/cluster_options.h"
#include "cmd/commands.h"
#include "cmd/plugin_options.h"
#include "drawing/plot_workers.h"
#include "harness/sweep/suite.h"
#include "harness/sweep/suite_runner.h"
#include "reports/run_pages.h"
#include "reports/viewer.h"

namespace aoeval {

RunOutcome run_suite_with_report(const SuiteRunOptions& o) {
  // The runner runs, stores and, still holding its folder, writes the pages from the store with
  // the page writer handed to it here, so that the runner never links reports/.
  SuiteRunOptions with_pages = o;
  with_pages.prestart_plot_workers = true;
  with_pages.pages = [](const std::string& dir, const std::string& database) {
    const std::string page = write_run_pages(dir, database);
    PlotWorkers::instance().stop();
    return page;
  };
  SuiteRun run = run_suite(with_pages);
  RunOutcome outcome;
  outcome.page = run.page;
  outcome.wall_ms = run.wall_ms;
  outcome.rows = run.rows;
  outcome.references = run.references;
  outcome.skipped = run.skipped;
  outcome.suite = run.suite;
  outcome.stages = std::move(run.stages);
  return outcome;
}

void add_run_command(CLI::App& app) {
  static SuiteRunOptions o;
  auto* cmd = app.add_subcommand("run", "run a suite and write its HTML report");
  cmd->add_option("--suite", o.suite,
                  "quick, default or paper (harness/suites/NAME.json), or a suite file: a list of "
                  "sweep specifications (CONTRACT §5)");
  cmd->add_option("--out", o.out_dir, "output folder (default: out/SUITE)");
  cmd->add_option("--db", o.database, "SQLite results store");
  add_plugins_option(cmd);
  cmd->add_option(
      "--set", o.sets,
      "ESTIMATOR:KEY=VALUE: replaces KEY's value in every run of ESTIMATOR (repeatable)");
  cmd->add_option("--shard", o.shard,
                  "run shard I of N (0-based) of the suite's points; auto: SLURM_ARRAY_TASK_ID of "
                  "SLURM_ARRAY_TASK_COUNT (merge the shards with `aoeval merge`)");
  cmd->add_option("--shard-plan", o.shard_plan,
                  "with --shard: the cost-balanced plan's shard (written by --slurm)");
  static bool viewer_exact = false;
  cmd->add_flag("--viewer-exact", viewer_exact,
                "the viewer's data, kept references and sequence frames as the EXRs' float32s, "
                "exactly (default: compact, float16 where that keeps every value within 1e-3, "
                "deflated; about 10x smaller)");
  static ClusterOptions c;
  add_cluster_options(cmd, c);
  cmd->add_flag("--resume", c.resume,
                "with --slurm: resubmit only the shards of --out that did not finish, then merge");
  cmd->callback([cmd] {
    if (c.resume && !c.slurm)
      throw InputError(
          "--resume: `aoeval run` resumes only with --slurm (a single-machine run "
          "is one pass; use `aoeval sweep --resume` for an interruptible one)");
    check_cluster_options(cmd, c);
    if (viewer_exact) set_default_viewer_data(ViewerData::exact);
    o.exact_kept_files = viewer_exact;
    if (c.slurm || c.references_only) {
      Suite suite = load_suite(o.suite);
      std::vector<SuiteOverride> overrides;
      for (const auto& s : o.sets) overrides.push_back(parse_suite_override(s));
      apply_suite_overrides(suite, overrides);
      const std::vector<SuitePoint> points = expand_suite(suite);
      std::vector<StagePoint> stage;
      for (const auto& p : points) stage.push_back({&p.point, &suite.specs[p.spec]});
      if (c.references_only) return run_reference_stage(stage, o.shard);
      SlurmSubmission s;
      s.command = "run";
      const bool is_file = o.suite.find('/') != std::string::npos ||
                           (o.suite.size() > 5 && o.suite.ends_with(".json"));
      s.input_args = {"--suite", is_file ? std::filesystem::absolute(o.suite).string() : o.suite};
      for (const auto& set : o.sets) {
        s.input_args.push_back("--set");
        s.input_args.push_back(set);
      }
      add_plugin_args(cmd, s.input_args);
      s.name = suite.name;
      s.out = o.out_dir;
      s.database = o.database;
      s.resume = c.resume;
      s.suite = true;
      s.points = stage;
      s.cluster = c;
      return submit_to_slurm(s);
    }
    const RunOutcome run = run_suite_with_report(o);
    std::fprintf(stderr, "run %s: time by stage\n%s", run.suite.c_str(),
                 run.stages.table(run.wall_ms).c_str());
    std::fprintf(stderr, "run %s: %llu references traced in %llu passes, %.3f Grays\n",
                 run.suite.c_str(), static_cast<unsigned long long>(run.references.references),
                 static_cast<unsigned long long>(run.references.traces),
                 static_cast<double>(run.references.rays) / 1e9);
    std::fprintf(stderr, "run %s: %zu rows (%zu skipped) in %.0f s\n", run.suite.c_str(), run.rows,
                 run.skipped, run.wall_ms / 1000.0);
    std::printf("%s\n", run.page.c_str());
  });
}

}  // namespace aoeval
