#include "harness/cluster/slurm_submit.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "estimators/plugins/plugin_process.h"
#include "harness/results/results_store.h"
#include "harness/sweep/shard_plan.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

namespace {

std::string join_quoted(const std::vector<std::string>& args) {
  std::string s;
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict, PR 105329) on " " + std::string.
  for (const auto& a : args) s.append(" ").append(shell_quote(a));
  return s;
}

void write_script(const fs::path& path, const std::string& body) {
  write_text(path.string(),
             "#!/bin/bash\n# Written by aoeval --slurm (harness/cluster/slurm_submit.h).\n" + body);
  fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                            fs::perms::others_read | fs::perms::others_exec);
}

// Runs sbatch --parsable with `args` (argv, no shell) for at most `timeout_s` and returns the job
// id. Every way it can fail is the user's Slurm set-up (not installed, not configured, the
// controller unreachable or refusing), so each is an InputError (exit 2) quoting sbatch.
std::string sbatch(const std::vector<std::string>& args, const fs::path& scratch,
                   double timeout_s) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), args.begin(), args.end());
  const fs::path out_file = scratch / ".sbatch-stdout", err_file = scratch / ".sbatch-stderr";
  const ProcessOutcome r = run_process(argv, ".", timeout_s, out_file, err_file);
  std::string out;
  {
    std::ifstream in(out_file);
    std::getline(in, out);
  }
  const std::string message = last_line_of(err_file);
  std::error_code ec;
  fs::remove(out_file, ec);
  fs::remove(err_file, ec);
  if (!r.started) throw InputError("--slurm: cannot run sbatch: " + r.error);
  if (r.timed_out) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%g", timeout_s);
    throw InputError(std::string("--slurm: sbatch did not answer within ") + seconds +
                     " s (--sbatch-timeout) and was stopped: is the Slurm controller reachable "
                     "(`sinfo`)?");
  }
  if (r.exit_code == 127)
    throw InputError("--slurm: cannot run sbatch (Slurm's client tools are needed on PATH)" +
                     (message.empty() ? std::string() : ": " + message));
  if (r.exit_code != 0) {
    const std::string how = r.signal ? "killed by signal " + std::to_string(r.signal)
                                     : "exit " + std::to_string(r.exit_code);
    throw InputError("--slurm: sbatch failed (" + how + ")" +
                     (message.empty() ? std::string() : ": " + message));
  }
  // --parsable prints "<id>" or "<id>;<cluster>".
  const std::string id = out.substr(0, out.find(';'));
  if (id.empty() || id.size() > 20 || id.find_first_not_of("0123456789") != std::string::npos) {
    std::string shown = out.size() > 60 ? out.substr(0, 57) + "..." : out;
    for (char& c : shown)
      if (static_cast<unsigned char>(c) < 0x20) c = '?';
    throw InputError("--slurm: sbatch printed no job id (its first line: '" + shown + "')");
  }
  return id;
}

// Cancels jobs submitted before a later submission failed (best effort, bounded like sbatch), so a
// half-submitted run does not go on without its merge.
void cancel(const std::vector<std::string>& jobs, const fs::path& scratch, double timeout_s) {
  if (jobs.empty()) return;
  std::vector<std::string> argv = {"scancel"};
  argv.insert(argv.end(), jobs.begin(), jobs.end());
  const fs::path out_file = scratch / ".scancel-stdout", err_file = scratch / ".scancel-stderr";
  run_process(argv, ".", timeout_s, out_file, err_file);
  std::error_code ec;
  fs::remove(out_file, ec);
  fs::remove(err_file, ec);
}

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("aoeval") : p.string();
}

std::string array_spec(const std::vector<int>& tasks) {
  std::string s;
  for (int t : tasks) s.append(s.empty() ? "" : ",").append(std::to_string(t));
  return s;
}

// The submission itself; `jobs` collects the ids submitted, for submit_to_slurm to cancel when a
// later step fails.
void submit(const SlurmSubmission& s, const fs::path& out, std::vector<std::string>& jobs) {
  const fs::path slurm_dir = out / "slurm", logs = slurm_dir / "logs";
  const fs::path plan_path = slurm_dir / "plan.json";
  const double timeout_s = s.cluster.sbatch_timeout_s;
  fs::create_directories(logs);
  const std::string db = fs::weakly_canonical(fs::absolute(s.database)).string();

  std::vector<std::string> names;
  for (const auto& p : s.points) names.push_back(p.point->name);
  ShardPlan plan;
  if (s.resume && fs::exists(plan_path)) {
    plan = read_shard_plan(plan_path.string());
    planned_shard(plan, names, 0, plan.shards, plan_path.string());  // the spec is unchanged
  } else {
    std::vector<ResultRow> history;
    if (fs::exists(s.database)) {
      try {
        history = SqliteStore(s.database, SqliteStore::Mode::read_only).all_rows();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "--slurm: no cost history (%s); estimating from defaults\n", e.what());
      }
    }
    const CostModel model(history);
    std::vector<PointCost> costs;
    for (const auto& p : s.points) costs.push_back(model.estimate(*p.point, p.spec->timing));
    const int n = std::max(1, std::min<int>(s.cluster.shards, static_cast<int>(names.size())));
    plan = plan_shards(costs, n);
    write_shard_plan(plan_path.string(), plan);
  }
  const int n = plan.shards;
  auto shard_dir = [&](int i) {
    return out / "shards" / ("shard-" + std::to_string(i) + "-of-" + std::to_string(n));
  };
  std::vector<int> unfinished_shards;
  for (int i = 0; i < n; ++i)
    if (!fs::exists(shard_dir(i) / "shard.json")) unfinished_shards.push_back(i);

  const std::string exe = self_exe();
  const std::string common = join_quoted(s.input_args);
  const std::vector<std::string>& extra = s.cluster.slurm_args;
  std::string references_job, shards_job;
  if (!unfinished_shards.empty()) {
    const size_t refs = distinct_references(s.points).size();
    if (refs > 0) {
      const int tasks = static_cast<int>(std::min<size_t>(refs, static_cast<size_t>(n)));
      write_script(slurm_dir / "references.sh", "exec " + shell_quote(exe) + " " + s.command +
                                                    common + " --references-only --shard auto\n");
      std::vector<std::string> args = {"--job-name=aoeval-" + s.name + "-references",
                                       "--array=0-" + std::to_string(tasks - 1),
                                       "--output=" + (logs / "references-%a.log").string()};
      args.insert(args.end(), extra.begin(), extra.end());
      args.push_back((slurm_dir / "references.sh").string());
      references_job = sbatch(args, logs, timeout_s);
      jobs.push_back(references_job);
      std::printf("references: job %s (array of %d over %zu distinct references)\n",
                  references_job.c_str(), tasks, refs);
    }
    const std::string dir =
        (out / "shards").string() + "/shard-${SLURM_ARRAY_TASK_ID}-of-" + std::to_string(n);
    // A sweep shard resumes inside its folder (a requeued or resubmitted shard keeps its rows);
    // a suite shard is rerun whole. The shard count is the plan's, not SLURM_ARRAY_TASK_COUNT:
    // a --resume array holds only the unfinished tasks (e.g. --array=1 has a count of 1).
    write_script(
        slurm_dir / "shard.sh",
        "dir=\"" + dir + "\"\nmkdir -p \"$dir\"\nstart=$(date +%s.%N)\n" + shell_quote(exe) + " " +
            s.command + common + " --out \"$dir\" --shard \"${SLURM_ARRAY_TASK_ID}/" +
            std::to_string(n) + "\" --shard-plan " + shell_quote(plan_path.string()) +
            " --db \"$dir/results.sqlite\"" + (s.command == "sweep" ? " --resume" : "") +
            "\nrc=$?\n"
            "if [ $rc -eq 0 ]; then\n"
            "  wall=$(awk -v a=\"$start\" -v b=\"$(date +%s.%N)\" 'BEGIN { printf \"%.3f\", b - a "
            "}')\n"
            "  printf '{\"index\": %s, \"count\": %s, \"node\": \"%s\", \"wall_s\": %s}\\n' "
            "\"$SLURM_ARRAY_TASK_ID\" " +
            std::to_string(n) +
            " \"$(hostname)\" \"$wall\" "
            "> \"$dir/.shard.json.tmp\" && mv \"$dir/.shard.json.tmp\" \"$dir/shard.json\"\n"
            "fi\nexit $rc\n");
    std::vector<std::string> args = {"--job-name=aoeval-" + s.name + "-shards",
                                     "--array=" + array_spec(unfinished_shards),
                                     "--output=" + (logs / "shard-%a.log").string()};
    if (!references_job.empty()) {
      args.push_back("--dependency=afterok:" + references_job);
      args.push_back("--kill-on-invalid-dep=yes");  // a failed reference stage cancels them
    }
    args.insert(args.end(), extra.begin(), extra.end());
    args.push_back((slurm_dir / "shard.sh").string());
    shards_job = sbatch(args, logs, timeout_s);
    jobs.push_back(shards_job);
    std::printf("shards: job %s (array %s of %d, planned slowest/mean %.3f)\n", shards_job.c_str(),
                array_spec(unfinished_shards).c_str(), n, plan.planned_ratio());
  }
  std::string dirs;
  for (int i = 0; i < n; ++i) dirs.append(" ").append(shell_quote(shard_dir(i).string()));
  write_script(slurm_dir / "merge.sh", "exec " + shell_quote(exe) + " merge" + dirs + " --out " +
                                           shell_quote(out.string()) + " --db " + shell_quote(db) +
                                           " --plan " + shell_quote(plan_path.string()) + "\n");
  std::vector<std::string> args = {"--job-name=aoeval-" + s.name + "-merge",
                                   "--output=" + (logs / "merge.log").string()};
  if (!shards_job.empty()) args.push_back("--dependency=afterany:" + shards_job);
  args.insert(args.end(), extra.begin(), extra.end());
  args.push_back((slurm_dir / "merge.sh").string());
  const std::string merge_job = sbatch(args, logs, timeout_s);
  jobs.push_back(merge_job);
  std::printf("merge: job %s (log %s)\n", merge_job.c_str(), (logs / "merge.log").c_str());
  std::printf("%s\n", (out / (s.suite ? "index.html" : "results.csv")).c_str());
}

}  // namespace

void submit_to_slurm(const SlurmSubmission& s) {
  if (s.cluster.shards < 1) throw InputError("--shards: must be at least 1");
  const fs::path out = fs::weakly_canonical(fs::absolute(s.out.empty() ? "out/" + s.name : s.out));
  if (!s.resume && (fs::exists(out / "results.json") || fs::exists(out / "slurm" / "plan.json")))
    throw InputError(out.string() +
                     ": already holds a run; pass --resume to continue it, or choose --out");
  // A submission that fails leaves nothing behind (else the retry would find plan.json and say
  // "already holds a run"): what this call created is removed, what it submitted cancelled.
  std::error_code ec;
  const bool out_existed = fs::exists(out, ec), slurm_existed = fs::exists(out / "slurm", ec);
  fs::path created = out;  // the topmost folder a submission into a new `out` creates
  while (!fs::exists(created.parent_path(), ec) && created.parent_path() != created)
    created = created.parent_path();
  std::vector<std::string> jobs;
  auto undo = [&] {
    cancel(jobs, out / "slurm" / "logs", s.cluster.sbatch_timeout_s);  // jobs: the folder exists
    if (!out_existed) {
      fs::remove_all(created, ec);
    } else if (!slurm_existed) {
      fs::remove_all(out / "slurm", ec);
    }
  };
  try {
    submit(s, out, jobs);
  } catch (const InputError& e) {
    std::string cancelled;
    for (const auto& id : jobs)
      cancelled.append(cancelled.empty() ? " (cancelled: job " : ", ").append(id);
    if (!cancelled.empty()) cancelled += ")";
    undo();
    throw InputError(e.what() + cancelled);
  } catch (...) {
    undo();
    throw;
  }
}

}  // namespace aoeval
