// `aoeval bench harness [--suite S] [--repetitions N]`: how much of a suite's wall time is the
// estimators' own (issue 16). A first run fills the reference cache (and is reported as such);
// then N runs, each into a fresh folder and database, give every stage's median and the median
// estimator share of wall time (precompute + warm-up + timed frames, over the whole `aoeval run`
// including its report). References are read from the cache in those runs, so what is left
// besides the estimators is the harness: scenes, G-buffers, scoring, images, results, report.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "base/summary.h"
#include "cmd/commands.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

struct HarnessBenchOptions {
  std::string suite = "quick";
  int repetitions = 3;
  std::string work_dir;  // default: a folder under the system's temporary folder
};

RunOutcome run_into(const HarnessBenchOptions& o, const fs::path& dir) {
  SuiteRunOptions run;
  run.suite = o.suite;
  run.out_dir = (dir / "out").string();
  run.database = (dir / "results.sqlite").string();
  return run_suite_with_report(run);
}

void bench_harness(const HarnessBenchOptions& o) {
  const fs::path work = o.work_dir.empty()
                            ? fs::temp_directory_path() / ("aoeval-bench-harness-" + o.suite)
                            : fs::path(o.work_dir);
  fs::remove_all(work);
  const RunOutcome first = run_into(o, work / "first");
  std::printf(
      "bench harness: suite %s, %zu rows; first run (references computed or read): "
      "%.1f s, estimator share %.1f %%\n",
      o.suite.c_str(), first.rows, first.wall_ms / 1000.0,
      100.0 * first.stages.estimator_ms() / first.wall_ms);
  std::fflush(stdout);
  std::vector<double> wall, share;
  std::vector<std::string> order;
  std::map<std::string, std::vector<double>> per_stage;
  for (int rep = 0; rep < o.repetitions; ++rep) {
    const RunOutcome r = run_into(o, work / ("run-" + std::to_string(rep)));
    wall.push_back(r.wall_ms);
    share.push_back(100.0 * r.stages.estimator_ms() / r.wall_ms);
    for (const auto& [stage, ms] : r.stages.entries()) {
      if (!per_stage.count(stage)) order.push_back(stage);
      per_stage[stage].push_back(ms);
    }
    std::printf("  run %d: %.1f s, estimator share %.1f %%\n", rep + 1, r.wall_ms / 1000.0,
                share.back());
    std::fflush(stdout);
  }
  StageTimes medians;
  for (const auto& stage : order) medians.add(stage, median(per_stage[stage]));
  std::printf(
      "cached runs, median of %d (each stage's median; the shares are of the median "
      "wall time):\n%s",
      o.repetitions, medians.table(median(wall)).c_str());
  std::printf("estimator share of wall time: median %.1f %% (runs: ", median(share));
  for (size_t k = 0; k < share.size(); ++k) std::printf("%s%.1f", k ? ", " : "", share[k]);
  std::printf(")\n");
  fs::remove_all(work);
}

}  // namespace

void add_bench_harness_command(CLI::App& bench) {
  static HarnessBenchOptions o;
  auto* cmd = bench.add_subcommand(
      "harness",
      "a suite's wall time by stage, and the estimators' share of it (cached references)");
  cmd->add_option("--suite", o.suite, "quick, default or paper, or a suite file")
      ->capture_default_str();
  cmd->add_option("--repetitions", o.repetitions, "cached runs after the first")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--work-dir", o.work_dir, "scratch folder for the runs (removed afterwards)");
  cmd->callback([] { bench_harness(o); });
}

}  // namespace aoeval
