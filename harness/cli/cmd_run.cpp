// `aoeval run [--suite default|quick|paper|FILE.json] [--out DIR] [--db FILE]
//  [--set ESTIMATOR:KEY=VALUE]...`: the main job (CONTRACT §2). References and every estimator over
// the suite's scenes, metrics, error maps, timing tables and the HTML report, whose path is the
// last line on stdout.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "harness/cli/commands.h"
#include "harness/plugins/plugin_options.h"
#include "harness/sweep/suite_runner.h"
#include "reports/gbuffer_gallery.h"
#include "reports/suite_report.h"

namespace aoeval {

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
  cmd->callback([] {
    // The runner runs and stores; the pages are written here, so the runner never links reports/.
    const auto t0 = std::chrono::steady_clock::now();
    SuiteRun run = run_suite(o);
    if (!run.gallery.empty()) {
      const auto timer = run.stages.time("G-buffer gallery page");
      write_gbuffer_gallery((std::filesystem::path(run.out_dir) / "gbuffers").string(),
                            run.report.suite, run.gallery);
      run.report.gbuffer_gallery = "gbuffers/index.html";
    }
    run.report.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string page;
    {
      const auto timer = run.stages.time("report (page, plots)");
      page = write_suite_report(run.out_dir, run.report);
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Where the time went, on stderr and in the run's context (issue 16).
    RunContext context = run.report.context;
    context.stages_ms = run.stages.to_json();
    context.stages_ms["wall"] = wall_s * 1000.0;
    record_run_context(run, context);
    std::fprintf(stderr, "run %s: time by stage\n%s", run.report.suite.c_str(),
                 run.stages.table(wall_s * 1000.0).c_str());
    std::fprintf(stderr, "run %s: %zu rows (%zu skipped) in %.0f s\n", run.report.suite.c_str(),
                 run.report.entries.size(), run.skipped, wall_s);
    std::printf("%s\n", page.c_str());
  });
}

}  // namespace aoeval
