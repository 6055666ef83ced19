#include "harness/sweep/sweep_runner.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "base/errors.h"
#include "base/text_files.h"
#include "harness/evaluation/background_lane.h"
#include "harness/evaluation/progress.h"
#include "harness/results/output_lock.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "harness/results/stage_times.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/kept_references.h"
#include "harness/sweep/kept_sequence.h"
#include "harness/sweep/shard_plan.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// The sweep's suite_record.json: every row's kept references, none featured (its report features
// the Pareto fronts), so that `aoeval merge` of its shards writes its page too.
void write_record(const std::string& out, const std::string& name, const std::string& spec_path,
                  const RunContext& context, double wall_s, const std::vector<ResultRow>& rows,
                  const std::map<std::string, SuiteReportEntry>& kept) {
  SuiteReport report;
  report.suite = name;
  report.suite_file = spec_path;
  report.context = context;
  report.wall_s = wall_s;  // this invocation's (a resumed sweep's page says the last part's)
  report.sweep = true;
  for (const ResultRow& r : rows) {
    SuiteReportEntry e;
    if (const auto it = kept.find(r.run_name); it != kept.end()) e = it->second;
    e.row.run_name = r.run_name;
    e.featured = false;
    report.entries.push_back(e);
  }
  write_suite_record(out, report, {});
}

}  // namespace

int run_sweep(const SweepOptions& o, std::string* out_dir, std::string* page) {
  const auto t_start = std::chrono::steady_clock::now();
  StageTimes runner_stages;
  const SweepSpec spec = load_sweep_spec(o.spec_path);
  std::vector<SweepPoint> points = expand_sweep(spec, o.max_points);
  const size_t total = points.size();
  {
    std::vector<std::string> names;
    for (const auto& p : points) names.push_back(p.name);
    check_file_stems(names, o.spec_path);  // before a shard is taken
    std::vector<SweepPoint> selected;
    for (size_t i : shard_indices(names, o.shard, o.shard_plan)) selected.push_back(points[i]);
    points = std::move(selected);
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
  // Inputs first: a bad --out, or a results.json that --resume cannot read, fails before the
  // database or the folder is created.
  check_output_folder(out);
  const fs::path results_json = fs::path(out) / "results.json";
  auto refuse_existing_results = [&] {
    if (!o.resume && fs::exists(results_json))
      throw InputError(out +
                       ": already holds results; pass --resume to continue it, or choose --out");
  };
  refuse_existing_results();
  if (o.resume && fs::exists(results_json)) read_results_file(results_json.string());
  // The recorder's order (run_recorder.h) is what makes a sweep safe to kill at any instant and
  // resume without losing or duplicating a row: database, folder lock, leftovers of killed writes,
  // results.json with the run id before any row reaches the database, then each row to SQLite
  // first and to the files after.
  RunRecorder recorder(out, o.database,
                       "sweep " + spec.name + (o.shard.empty() ? "" : " --shard " + o.shard),
                       FolderAccess::exclusive);
  // The dashboard finds a run's estimate images through this folder.
  recorder.context().output_dir = fs::absolute(out).lexically_normal().string();
  std::set<std::string> done;
  // What the report needs besides the rows (suite_record_io.h): the references each row was scored
  // against, kept under <out>/references/; a resumed sweep keeps those of its earlier part.
  std::map<std::string, SuiteReportEntry> kept;
  if (o.resume && has_suite_record(out)) kept = read_suite_record(out).entries;
  // Bit for bit: a sweep is what users rescore (`compare --sequence` on its kept files must give
  // the row's keys exactly); the float16 rounding is for `aoeval run`'s report folder.
  KeptReferences references(out, /*exact=*/true);
  if (o.resume) {
    recorder.resume();
    for (const ResultRow& r : recorder.rows()) done.insert(r.run_name);
  } else {
    refuse_existing_results();  // written between the first check and the lock
  }
  recorder.write_files();  // also repairs a CSV that lagged behind results.json
  recorder.register_run();

  std::vector<const SweepPoint*> pending;
  for (const auto& p : points)
    if (!done.count(p.name)) pending.push_back(&p);
  std::fprintf(stderr, "sweep %s: %zu points (%zu in this shard), %zu already done, %zu to run\n",
               spec.name.c_str(), total, points.size(), points.size() - pending.size(),
               pending.size());

  std::optional<InterruptScope> interrupts(std::in_place);  // SIGINT stops between two points
  EvaluationSession session(spec.reference, spec.timing);
  // The record is written when an invocation ends, so a SIGKILLed one leaves rows without their
  // kept references: a resume keeps them again (from the reference cache) for every finished ok
  // row the record lacks, so the page shows every row, not only those of the last invocation.
  if (o.resume && o.keep_estimates) {
    std::map<std::string, const ResultRow*> finished_rows;
    for (const ResultRow& r : recorder.rows()) finished_rows[r.run_name] = &r;
    for (const auto& p : points) {
      const auto row = finished_rows.find(p.name);
      if (row == finished_rows.end() || row->second->status != "ok" ||
          row->second->estimate_file.empty() || kept.count(p.name))
        continue;
      const auto timer = runner_stages.time("references copied");
      const View& view = session.scene(p.scene).scene.view(p.view);
      const ParamSet params = resolve_params(p.estimator->name, p.estimator->params, p.overrides,
                                             "estimator " + p.estimator->name);
      SuiteReportEntry& entry = kept[p.name];
      entry.reference_exr = references.keep(session, p.scene, view, p.width, p.height,
                                            p.estimator->definition(params));
      entry.true_reference_exr =
          references.keep(session, p.scene, view, p.width, p.height, true_ao_definition());
    }
  }
  // Every point's references declared first: each trace serves every definition of its
  // weighting the sweep asks of that view (issue 42).
  for (const SweepPoint* p : pending) session.plan_references(evaluation_request(*p));
  Progress progress("sweep " + spec.name, pending.size());
  size_t finished = 0;
  {
    // Scoring and the row's writes run here while the next points' estimators get ready; the
    // session pauses the lane during every timed frame loop (background_lane.h).
    BackgroundLane lane;
    session.set_timed_frames_guard([&lane] { lane.pause(); }, [&lane] { lane.resume(); });
    session.set_background([&lane](std::function<void()> job) { lane.post(std::move(job)); });
    for (const SweepPoint* p : pending) {
      if (interrupts->interrupted()) break;
      auto measured = std::make_shared<Measurement>(session.measure(evaluation_request(*p)));
      auto finish = [&, p, measured] {
        const std::string estimate_rel = "estimates/" + file_stem_for(p->name) + ".exr";
        ResultRow row = session.score(
            *measured, o.keep_estimates ? (fs::path(out) / estimate_rel).string() : "");
        if (o.keep_estimates && row.status == "ok") {
          row.estimate_file = estimate_rel;
          const auto timer = runner_stages.time("references copied");
          const View& view = session.scene(p->scene).scene.view(p->view);
          SuiteReportEntry& entry = kept[row.run_name];
          entry.reference_exr = references.keep(session, p->scene, view, p->width, p->height,
                                                p->estimator->definition(measured->params));
          entry.true_reference_exr =
              references.keep(session, p->scene, view, p->width, p->height, true_ao_definition());
        }
        std::vector<KeptImage> sequence_images;
        if (!measured->frames.empty()) {  // before the row: a committed row has its frames
          const auto timer = runner_stages.time("sequence frames kept");
          sequence_images =
              keep_sequence(out, "", *p, *measured, session, references, o.keep_estimates);
        }
        SuiteReportEntry entry;  // the kept references, when the sweep keeps them
        if (const auto k = kept.find(row.run_name); k != kept.end()) entry = k->second;
        entry.row = row;
        // Stamped with the run; SQLite (row, frames, images), then the files.
        recorder.record(
            point_record(entry, frame_rows(measured->frames), std::move(sequence_images)),
            &runner_stages);
        ++finished;
      };
      {
        const auto timer = runner_stages.time(StageTimes::kWaitingForBackground);  // a full queue
        lane.post(std::move(finish));
      }
      const EvaluationSession::ReferenceCounts refs = session.reference_counts();
      progress.note("references " + std::to_string(refs.references) + " traced in " +
                    std::to_string(refs.traces) + " passes");
      progress.step(p->name);
    }
    // An interrupted sweep still keeps the row of every point it measured.
    const auto timer = runner_stages.time(StageTimes::kBackgroundLeftAtEnd);
    lane.drain();
    session.set_timed_frames_guard(nullptr, nullptr);
    session.set_background(nullptr);
  }
  interrupts.reset();  // the handler it replaced is back
  // The breakdown of this invocation (a resumed sweep reports the part it ran), on stderr and in
  // the run's context.
  StageTimes stages = session.stages();
  stages.add_all(runner_stages);
  const auto wall_ms_now = [&] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start)
        .count();
  };
  recorder.context().stages_ms = stages.to_json();
  recorder.context().stages_ms["wall"] = wall_ms_now();
  write_record(out, spec.name, o.spec_path, recorder.context(), wall_ms_now() / 1000.0,
               recorder.rows(), kept);
  if (out_dir) *out_dir = out;
  const bool stopped = interrupt_requested() && finished < pending.size();
  // As `run` does (suite_runner.cpp): the pages from what the store now holds, the folder still
  // locked and their time among the stages; then the run's context with where the time went. A
  // page writer that throws still leaves the run registered.
  if (o.pages && !stopped) {
    recorder.write_files();
    try {
      const auto timer = stages.time("report (page, plots)");
      const std::string written = o.pages(out, o.database);
      if (page) *page = written;
    } catch (...) {
      recorder.register_run();
      throw;
    }
  }
  const double wall_ms = wall_ms_now();
  recorder.context().stages_ms = stages.to_json();
  recorder.context().stages_ms["wall"] = wall_ms;
  recorder.write_files();
  recorder.register_run();
  std::fprintf(stderr, "sweep %s: time by stage\n%s", spec.name.c_str(),
               stages.table(wall_ms).c_str());
  const EvaluationSession::ReferenceCounts refs = session.reference_counts();
  std::fprintf(stderr, "sweep %s: %llu references traced in %llu passes, %.3f Grays\n",
               spec.name.c_str(), static_cast<unsigned long long>(refs.references),
               static_cast<unsigned long long>(refs.traces), static_cast<double>(refs.rays) / 1e9);
  if (stopped) {
    std::fprintf(stderr, "sweep %s: interrupted after %zu of %zu points; rerun with --resume\n",
                 spec.name.c_str(), finished, pending.size());
    return 130;
  }
  std::printf("%s", console_table(recorder.rows(), {"run_name", "rmse", "rmse_excess", "ssim",
                                                    "true_rmse", "time_ms_median"})
                        .c_str());
  return 0;
}

}  // namespace aoeval
