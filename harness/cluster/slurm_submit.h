// `aoeval sweep SPEC --slurm` and `aoeval run --suite S --slurm` (CONTRACT §9, issue 19): three
// sbatch submissions, chained by dependencies, over one output folder OUT:
//   1. references  an array over the distinct references (reference_stage.h), into the shared
//                  AOEVAL_CACHE;
//   2. shards      an array of N estimator shards, --dependency=afterok on 1, each running
//                  `aoeval sweep|run ... --shard auto --shard-plan OUT/slurm/plan.json` into
//                  OUT/shards/shard-I-of-N with its own SQLite file (SQLite on a network file
//                  system is not safe for many writers), and writing shard.json (node, wall time)
//                  when it succeeds;
//   3. merge       `aoeval merge OUT/shards/* --out OUT --db DB --plan PLAN`, with
//                  --dependency=afterany on 2: afterok would leave it pending for ever
//                  (DependencyNeverSatisfied) when a shard fails, so nobody would read why; this
//                  way it runs, names the incomplete shards and fails.
// The plan balances the shards by estimated cost (sweep/shard_plan.h). `--resume` reuses OUT's
// plan and resubmits only the shards without a shard.json; sweep shards also resume inside their
// folder, so a failed shard keeps the rows it finished.
#pragma once

#include <string>
#include <vector>

#include "harness/cluster/reference_stage.h"

namespace aoeval {

struct ClusterOptions {
  bool slurm = false;
  std::vector<std::string> slurm_args;  // passed to every sbatch, in order
  int shards = 4;
  bool references_only = false;  // the reference stage's job (hidden option)
  bool resume = false;           // `run --resume` (sweep has its own --resume)
  // Each sbatch (and the scancel of a failed submission) is stopped after this long: a controller
  // that does not answer must not hang aoeval.
  double sbatch_timeout_s = 60.0;
};

struct SlurmSubmission {
  std::string command;  // "sweep" or "run"
  // What every job passes to aoeval before its own options: {"SPEC.json"} for sweep,
  // {"--suite", "S"} for run, plus --plugins, --set, --max-points as given.
  std::vector<std::string> input_args;
  std::string name;  // the spec's or suite's name, for job names
  std::string out;   // the merged folder
  std::string database;
  bool resume = false;
  bool suite = false;  // a suite writes index.html
  std::vector<StagePoint> points;
  ClusterOptions cluster;
};

// Plans, writes OUT/slurm/{plan.json,*.sh}, submits, prints the job ids and, last on stdout, the
// path of the merged report (OUT/index.html for a suite, OUT/results.csv for a sweep). InputError
// (exit 2) for an output folder that already holds results without --resume, and when sbatch
// cannot be run, fails, prints no job id or does not answer within sbatch_timeout_s (quoting
// sbatch's last stderr line). A failed submission leaves nothing behind: the folders it created
// are removed, the jobs it had already submitted cancelled (scancel), so a retry starts afresh.
void submit_to_slurm(const SlurmSubmission& submission);

// POSIX shell quoting: 'text' with each ' written '\''.
std::string shell_quote(const std::string& text);

}  // namespace aoeval
