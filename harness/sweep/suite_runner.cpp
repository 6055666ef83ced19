#include "harness/sweep/suite_runner.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <set>
#include <thread>

#include "base/errors.h"
#include "base/text_files.h"
#include "drawing/error_maps.h"
#include "drawing/gbuffer_previews.h"
#include "drawing/plot_workers.h"
#include "harness/evaluation/background_lane.h"
#include "harness/evaluation/evaluation.h"
#include "harness/evaluation/progress.h"
#include "harness/evaluation/repetition_policy.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "harness/results/suite_record.h"
#include "harness/results/suite_record_io.h"
#include "harness/sweep/kept_references.h"
#include "harness/sweep/kept_sequence.h"
#include "harness/sweep/shard_plan.h"
#include "harness/sweep/suite.h"
#include "harness/sweep/sweep_runner.h"
#include "scenes/corpus.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The run's own copy of its rows, <out>/runs/<run_id>/results.json, beside the folder's
// results.json that accumulates every run's rows. A folder's first run writes the same bytes to
// both (0.9 MB for the default suite): the copy is then a hard link to the folder's file, which
// a later run's atomic rewrite replaces by a new file, leaving the link as it was.
void write_run_results(const std::string& out, const RunRecorder& recorder) {
  const std::string path =
      (fs::path(out) / "runs" / recorder.context().run_id / "results.json").string();
  const std::string text = results_json(recorder.rows(), recorder.context());
  const fs::path folders = fs::path(out) / "results.json";
  std::error_code not_linked;
  if (fs::exists(folders) && fs::file_size(folders) == text.size()) {
    std::ifstream in(folders, std::ios::binary);
    const std::string there((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (there == text) {
      const std::string temp = temporary_path_for(path);
      fs::create_hard_link(folders, temp, not_linked);
      if (!not_linked) return commit_temporary(temp, path);
      discard_temporary(temp);
    }
  }
  write_text(path, text);
}

std::string resolution(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// Everything the run keeps besides the rows: references copied into <out>/references/ (once per
// run), mosaics, and the G-buffers for the gallery.
class RunImages {
 public:
  RunImages(std::string out, std::string run_dir, bool exact)
      : out_(std::move(out)), run_dir_(std::move(run_dir)), references_(out_, exact) {}
  bool exact() const { return references_.exact(); }

  // A sequence point's kept frames, references and manifest (kept_sequence.h).
  std::vector<KeptImage> keep_sequence(EvaluationSession& session, const SweepPoint& p,
                                       const Measurement& m, const std::string& run_dir) {
    return aoeval::keep_sequence(out_, run_dir, p, m, session, references_);
  }
  // The reference EXR for (scene, view, resolution, definition) under references/.
  std::string reference(EvaluationSession& session, const std::string& scene_name, const View& view,
                        int w, int h, const AoDefinition& definition) {
    return references_.keep(session, scene_name, view, w, h, definition);
  }

  OIIO::ImageBuf mosaic(EvaluationSession& session, const SweepPoint& p, const ResultRow& row,
                        const AoDefinition& definition) {
    const View& view = session.scene(p.scene).scene.view(p.view);
    const GBuffer& g = session.gbuffer(p.scene, view, p.width, p.height);
    const ReferenceImage& ref = session.reference(p.scene, view, p.width, p.height, definition);
    const std::vector<float>& est = session.last_estimate();
    std::vector<uint8_t> mask(g.pixel_count());
    for (size_t k = 0; k < mask.size(); ++k) mask[k] = g.covered(k) && ref.covered(k);
    char numbers[160];
    std::snprintf(numbers, sizeof numbers, "   rmse %.4f   ssim %.3f   flip %.3f",
                  row.metrics.value("rmse", 0.0), row.metrics.value("ssim", 0.0),
                  row.metrics.value("flip_mean", 0.0));
    return error_mosaic(g.width, g.height, ref.ao.data(), est.data(), mask,
                        std::string(p.name) + numbers);
  }
  // Writes a mosaic; returns its path relative to the output.
  std::string write_mosaic(const SweepPoint& p, const OIIO::ImageBuf& mosaic) {
    const std::string rel = run_dir_ + "/mosaics/" + file_stem_for(p.name) + ".png";
    write_image((fs::path(out_) / rel).string(), mosaic);
    return rel;
  }

  // The gallery's G-buffer EXR and previews of every (scene, view, resolution) the suite renders,
  // written when the view is first scored (on the background lane, so not in the wall time);
  // the page is written at the end from gallery().
  void note_view(EvaluationSession& session, const std::string& scene, const std::string& view_name,
                 int w, int h, StageTimes& stages) {
    const std::string key = scene + "|" + view_name + "|" + resolution(w, h);
    if (!seen_views_.insert(key).second) return;
    views_.push_back({scene, view_name, w, h});
    const auto& data = session.scene(scene);
    const View& view = data.scene.view(view_name);
    const std::string exr =
        (fs::path(out_) / "gbuffers" / gallery_exr(data.scene, view, w, h)).string();
    const OIIO::ImageBuf image = gbuffer_to_image(session.gbuffer(scene, view, w, h));
    {
      const auto timer = stages.time("G-buffer gallery EXRs");
      // PXR24 unless exact (issue 42: 9.9 -> 4.6 MB in the default report): every value to the
      // nearest of 15 mantissa bits, within 2^-16 of it relative (0.15 mm at 10 m); A and
      // objectId, integers, exact. The gallery's copy is for looking at; `aoeval gbuffer` writes
      // the exact one.
      write_exr(exr, image,
                gbuffer_attributes(data.scene, data.content_hash, view, make_camera(view, w, h)),
                exact() ? "zip" : "pxr24");
    }
    BackgroundLane::checkpoint();
    const auto timer = stages.time("G-buffer gallery previews");
    const GBufferPreviewPaths png = gbuffer_preview_paths(exr);
    write_gbuffer_previews(image, exr, png.normals, png.depth);
  }
  std::vector<GalleryEntry> gallery(EvaluationSession& session,
                                    const std::map<std::string, double>& load_ms) {
    std::vector<GalleryEntry> entries;
    for (const auto& v : views_) {
      const auto& data = session.scene(v.scene);
      const View& view = data.scene.view(v.view);
      GalleryEntry e;
      e.scene = data.scene.name;
      e.view = view.name;
      e.triangles = data.scene.triangle_count();
      e.objects = data.scene.objects.size();
      e.bvh_ms = data.embree->build_ms();
      e.load_ms = std::max(0.0, load_ms.at(v.scene) - e.bvh_ms);
      e.gbuffer_exr = gallery_exr(data.scene, view, v.w, v.h);
      entries.push_back(e);
    }
    return entries;
  }

 private:
  static std::string gallery_exr(const Scene& scene, const View& view, int w, int h) {
    return (fs::path("scenes") / scene.name / (view.name + "_" + resolution(w, h) + "_gbuffer.exr"))
        .string();
  }
  struct ViewUse {
    std::string scene, view;
    int w, h;
  };
  std::string out_, run_dir_;
  KeptReferences references_;
  std::set<std::string> seen_views_;
  std::vector<ViewUse> views_;
};

// Runs one point's estimator (on the runner's thread; the timed frames alone on the machine).
Measurement measure_point(const SuitePoint& sp, EvaluationSession& session) {
  const SweepPoint& p = sp.point;
  const EvaluationRequest req = evaluation_request(p);
  try {  // a missing backend (no Vulkan device) gives a "skipped: ..." row, not an exception
    return session.measure(req);
  } catch (const InputError& e) {
    throw InputError(p.name + ": " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(p.name + ": " + e.what());
  }
}

// Scores a measured point, keeps its estimate (and, when featured, its mosaic) and the references
// it was scored against (on the background lane, while the next point's estimator gets ready).
SuiteReportEntry finish_point(const SuitePoint& sp, Measurement& measured,
                              EvaluationSession& session, RunImages& images, const std::string& out,
                              const std::string& run_dir, StageTimes& stages,
                              std::vector<KeptImage>& sequence_images) {
  const SweepPoint& p = sp.point;
  const std::string estimate_rel = run_dir + "/estimates/" + file_stem_for(p.name) + ".exr";
  SuiteReportEntry entry;
  entry.featured = sp.featured;
  try {
    entry.row = session.score(measured, (fs::path(out) / estimate_rel).string());
  } catch (const InputError& e) {
    throw InputError(p.name + ": " + e.what());
  } catch (const std::exception& e) {
    throw std::runtime_error(p.name + ": " + e.what());
  }
  ResultRow& row = entry.row;  // stamped with the run when it is recorded
  if (row.status != "ok") return entry;
  if (!measured.frames.empty()) {  // before the row is committed: a committed row has its frames
    const auto timer = stages.time("sequence frames kept");
    sequence_images = images.keep_sequence(session, p, measured, run_dir);
  }
  row.estimate_file = estimate_rel;  // written compact by the session unless exact
  const AoDefinition definition = p.estimator->definition(measured.params);
  const View& view = session.scene(p.scene).scene.view(p.view);
  BackgroundLane::checkpoint();
  {
    const auto timer = stages.time("references copied");
    entry.reference_exr = images.reference(session, p.scene, view, p.width, p.height, definition);
    entry.true_reference_exr =
        images.reference(session, p.scene, view, p.width, p.height, true_ao_definition());
  }
  BackgroundLane::checkpoint();
  if (sp.featured) {
    OIIO::ImageBuf mosaic;
    {
      const auto timer = stages.time("mosaics");
      mosaic = images.mosaic(session, p, row, definition);
    }
    BackgroundLane::checkpoint();
    const auto timer = stages.time("mosaics");
    entry.mosaic_png = images.write_mosaic(p, mosaic);
  }
  images.note_view(session, p.scene, p.view, p.width, p.height, stages);
  BackgroundLane::checkpoint();
  return entry;
}

}  // namespace

SuiteRun run_suite(const SuiteRunOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  Suite suite = load_suite(o.suite);
  std::vector<SuiteOverride> overrides;
  for (const auto& s : o.sets) overrides.push_back(parse_suite_override(s));
  apply_suite_overrides(suite, overrides);
  std::vector<SuitePoint> points = expand_suite(suite);
  {
    std::vector<std::string> names;
    for (const auto& p : points) names.push_back(p.point.name);
    check_file_stems(names, "suite " + suite.name);
  }
  if (!o.shard.empty() || !o.shard_plan.empty()) {  // a shard of a --slurm run (CONTRACT §9)
    std::vector<std::string> names;
    for (const auto& p : points) names.push_back(p.point.name);
    std::vector<SuitePoint> selected;
    for (size_t i : shard_indices(names, o.shard, o.shard_plan)) selected.push_back(points[i]);
    points = std::move(selected);
  }

  const std::string out = o.out_dir.empty() ? "out/" + suite.name : o.out_dir;
  // Database first (an unwritable --db leaves no folder), then one writer per folder
  // (run_recorder.h: the order that makes results kill-safe). A suite run never resumes: its rows
  // replace the folder's results files, and the run is registered before its first row.
  std::string command = "run " + suite.name;
  for (const auto& s : o.sets) command += " --set " + s;
  if (!o.shard.empty()) command += " --shard " + o.shard;
  const auto recorder =
      std::make_unique<RunRecorder>(out, o.database, command, FolderAccess::exclusive);
  recorder->context().output_dir = fs::weakly_canonical(fs::absolute(out)).string();
  const RunContext& context = recorder->context();
  const std::string run_dir = "runs/" + context.run_id;
  recorder->register_run();

  std::set<std::string> scenes, estimators;
  for (const auto& p : points) {
    scenes.insert(p.point.scene);
    estimators.insert(p.point.estimator->name);
  }
  std::fprintf(stderr, "run %s: %zu points, %zu scenes, %zu estimators -> %s\n", suite.name.c_str(),
               points.size(), scenes.size(), estimators.size(), context.output_dir.c_str());

  // One session per (reference, timing) of the suite's specs; the shipped suites share one.
  std::map<std::string, std::unique_ptr<EvaluationSession>> sessions;
  auto session_for = [&](const SweepSpec& spec) -> EvaluationSession& {
    const std::string key = spec.reference.to_json().dump() + "|" + timing_key(spec.timing);
    auto& s = sessions[key];
    if (!s) {
      s = std::make_unique<EvaluationSession>(spec.reference, spec.timing);
      if (!o.exact_kept_files) s->set_estimate_writer(write_compact_estimate);
    }
    return *s;
  };

  RunImages images(out, run_dir, o.exact_kept_files);
  SuiteRun result;
  result.stages.add("run set-up (suite, store, machine and git probe)",
                    seconds_since(t_start) * 1000.0);
  result.suite = suite.name;
  result.out_dir = out;
  SuiteReport report;  // what suite_record.json keeps of it; the pages read the store
  report.suite = suite.name;
  report.suite_file = suite.path;
  report.overrides = o.sets;
  std::map<std::string, double> load_ms;  // scene -> load + BVH time of its first use
  size_t skipped = 0;
  {
    // Declared after everything its jobs use, so it finishes them before those go away.
    BackgroundLane lane;
    // The report's plot workers import matplotlib in the untimed stretches: the timed-frames
    // guard stops them (SIGSTOP) with the lane.
    PlotWorkers& plot_workers = PlotWorkers::instance();
    if (o.prestart_plot_workers)
      plot_workers.start(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
    const bool guard_workers = o.prestart_plot_workers;
    // Every point's references declared first, so that each trace serves every definition of
    // its weighting the suite asks of that view (issue 42).
    for (const SuitePoint& sp : points)
      session_for(suite.specs[sp.spec]).plan_references(evaluation_request(sp.point));
    Progress progress("run " + suite.name, points.size());
    for (const SuitePoint& sp : points) {
      EvaluationSession& session = session_for(suite.specs[sp.spec]);
      session.set_timed_frames_guard(
          [&lane, &plot_workers, guard_workers] {
            if (guard_workers) plot_workers.freeze();
            lane.pause();
          },
          [&lane, &plot_workers, guard_workers] {
            lane.resume();
            if (guard_workers) plot_workers.thaw();
          });
      session.set_background([&lane](std::function<void()> job) { lane.post(std::move(job)); });
      if (!load_ms.count(sp.point.scene)) {
        const auto t0 = std::chrono::steady_clock::now();
        session.scene(sp.point.scene);
        load_ms[sp.point.scene] = seconds_since(t0) * 1000.0;
      }
      auto measured = std::make_shared<Measurement>(measure_point(sp, session));
      auto finish = [&, measured, sp_ptr = &sp, session_ptr = &session] {
        std::vector<KeptImage> sequence_images;
        SuiteReportEntry entry = finish_point(*sp_ptr, *measured, *session_ptr, images, out,
                                              run_dir, result.stages, sequence_images);
        skipped += entry.row.status != "ok";
        entry.row = recorder->record(
            point_record(entry, frame_rows(measured->frames), std::move(sequence_images)),
            &result.stages);
        report.entries.push_back(std::move(entry));
      };
      {
        const auto timer = result.stages.time(StageTimes::kWaitingForBackground);  // a full queue
        lane.post(std::move(finish));
      }
      uint64_t traced = 0, passes = 0;
      for (auto& [key, one] : sessions) {
        traced += one->reference_counts().references;
        passes += one->reference_counts().traces;
      }
      progress.note("references " + std::to_string(traced) + " traced in " +
                    std::to_string(passes) + " passes");
      progress.step(sp.point.name);
    }
    {
      const auto timer = result.stages.time(StageTimes::kBackgroundLeftAtEnd);
      lane.drain();
    }
    for (auto& [key, session] : sessions) {
      session->set_timed_frames_guard(nullptr, nullptr);
      session->set_background(nullptr);
    }
  }
  {
    const auto timer = result.stages.time("results CSV + JSON");
    write_run_results(out, *recorder);
  }

  // The G-buffer gallery needs a session holding the scenes: every suite point used one.
  std::vector<GalleryEntry> gallery;
  if (!sessions.empty()) gallery = images.gallery(*sessions.begin()->second, load_ms);
  StageTimes stages;
  for (const auto& [key, session] : sessions) {
    stages.add_all(session->stages());
    const EvaluationSession::ReferenceCounts c = session->reference_counts();
    result.references.traces += c.traces;
    result.references.references += c.references;
    result.references.rays += c.rays;
  }
  stages.add_all(result.stages);
  result.stages = stages;
  report.context = context;
  report.wall_s = seconds_since(t_start);
  result.skipped = skipped;
  result.rows = recorder->rows().size();
  // The folder's record and results.json, then its pages from what the store holds (the folder's
  // lock held throughout), then the run's context with where the time went (issue 16).
  write_suite_record(out, report, gallery);
  if (o.pages) {  // a page writer that throws still leaves the run registered
    recorder->write_files();
    try {
      const auto timer = result.stages.time("report (page, plots)");
      result.page = o.pages(out, o.database);
    } catch (...) {
      recorder->register_run();
      throw;
    }
  }
  result.wall_ms = seconds_since(t_start) * 1000.0;
  nlohmann::json stages_ms = result.stages.to_json();
  stages_ms["wall"] = result.wall_ms;
  recorder->context().stages_ms = stages_ms;
  recorder->write_files();
  write_run_results(out, *recorder);
  recorder->register_run();
  return result;  // the recorder, and with it the lock, goes
}

}  // namespace aoeval
