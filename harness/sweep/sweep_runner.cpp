#include "harness/sweep/sweep_runner.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <set>

#include "errors.h"
#include "harness/evaluation/progress.h"
#include "harness/results/results_store.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_sigint(int) {
  g_interrupted = true;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

int run_sweep(const SweepOptions& o) {
  const SweepSpec spec = load_sweep_spec(o.spec_path);
  std::vector<SweepPoint> points = expand_sweep(spec);
  const size_t total = points.size();
  if (!o.shard.empty()) {
    const auto [index, count] = parse_shard(o.shard);
    points = select_shard(points, index, count);
  }
  // Shards default to a folder each, so that concurrent shards never rewrite each other's files.
  std::string out = o.out_dir;
  if (out.empty()) {
    out = "out/" + spec.name;
    if (!o.shard.empty()) {
      const auto [index, count] = parse_shard(o.shard);
      out += "/shard-" + std::to_string(index) + "-of-" + std::to_string(count);
    }
  }
  RunContext context =
      make_run_context("sweep " + spec.name + (o.shard.empty() ? "" : " --shard " + o.shard));
  // The dashboard finds a run's estimate images through this folder.
  context.output_dir = fs::absolute(out).lexically_normal().string();
  ResultsFolder folder(out, context);
  std::set<std::string> done;
  if (o.resume) {
    for (const auto& name : folder.load_existing()) done.insert(name);
  } else if (fs::exists(fs::path(out) / "results.json")) {
    throw InputError(out +
                     ": already holds results; pass --resume to continue it, or choose --out");
  }
  SqliteStore store(o.database);
  store.add_run(context);

  std::vector<const SweepPoint*> pending;
  for (const auto& p : points)
    if (!done.count(p.name)) pending.push_back(&p);
  std::fprintf(stderr, "sweep %s: %zu points (%zu in this shard), %zu already done, %zu to run\n",
               spec.name.c_str(), total, points.size(), points.size() - pending.size(),
               pending.size());

  g_interrupted = false;
  auto previous = std::signal(SIGINT, on_sigint);
  EvaluationSession session(spec.reference, spec.timing);
  Progress progress("sweep " + spec.name, pending.size());
  size_t finished = 0;
  for (const SweepPoint* p : pending) {
    if (g_interrupted) break;
    EvaluationRequest req;
    req.estimator = p->estimator;
    req.overrides = p->overrides;
    req.scene = p->scene;
    req.view = p->view;
    req.width = p->width;
    req.height = p->height;
    const std::string estimate_rel = "estimates/" + file_stem_for(p->name) + ".exr";
    ResultRow row =
        session.evaluate(req, o.keep_estimates ? (fs::path(out) / estimate_rel).string() : "");
    row.run_id = context.run_id;
    row.machine = context.machine;
    if (row.device.empty()) row.device = context.device;
    row.git_commit = context.git_commit;
    if (o.keep_estimates && row.status == "ok") row.estimate_file = estimate_rel;
    folder.add(row);
    store.add(row);
    ++finished;
    progress.step(p->name);
  }
  std::signal(SIGINT, previous == SIG_ERR ? SIG_DFL : previous);
  if (g_interrupted && finished < pending.size()) {
    std::fprintf(stderr, "sweep %s: interrupted after %zu of %zu points; rerun with --resume\n",
                 spec.name.c_str(), finished, pending.size());
    return 130;
  }
  std::printf("%s", console_table(folder.rows(), {"run_name", "rmse", "rmse_excess", "ssim",
                                                  "true_rmse", "time_ms_median"})
                        .c_str());
  std::printf("%s\n", (fs::path(out) / "results.csv").string().c_str());
  return 0;
}

}  // namespace aoeval
