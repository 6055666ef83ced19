// `aoeval bench rtao` (see bench_rtao.h).
#include "harness/bench/bench_rtao.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "base/errors.h"
#include "base/resolution.h"
#include "base/summary.h"
#include "base/text_files.h"
#include "estimators/pixel_loops.h"
#include "estimators/registry.h"
#include "harness/bench/bench_rows.h"
#include "harness/results/results_store.h"
#include "harness/results/run_recorder.h"
#include "scenes/corpus.h"

namespace aoeval {

namespace fs = std::filesystem;

void bench_rtao(const RtaoBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  const EstimatorInfo& e = find_estimator(o.estimator);
  if (!e.keeps_state)
    throw InputError("bench: " + e.name +
                     " keeps no state over a sequence (each frame would be a still frame); time it "
                     "with `aoeval bench estimators`");
  const nlohmann::json overrides = parse_set_arguments(o.sets);
  const ParamSet params = resolve_params(e.name, e.params, overrides, "bench --set");
  Scene scene = load_scene(o.scene);
  const View& view = scene.view(o.view);
  EmbreeScene es(scene);
  GBuffer g = render_gbuffer(es, make_camera(view, w, h));
  g.motion.assign(g.pixel_count(), glm::vec2(0.0f));  // a static camera: the sequence channels
  g.disoccluded.assign(g.pixel_count(), 0.0f);
  size_t covered = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) covered += g.covered(k) ? 1 : 0;

  // rtao's histories over the steady frames (a static camera: without the anti-lag frame k's is
  // min(k + 1, history_limit) everywhere): covered pixels counted shorter by more than half a
  // frame, and shorter than variance_frames (where the variance pass takes its spatial estimate).
  const bool rtao = e.name == "rtao";
  double shortened = 0.0, below_variance = 0.0, counted = 0.0;
  auto count_histories = [&](const EstimateResult& r, int k) {
    const auto it = r.extra_channels.find("history_length");
    if (!rtao || k == 0 || it == r.extra_channels.end()) return;
    const double full = std::min<double>(k + 1, params.integer("history_limit"));
    const double frames = static_cast<double>(params.integer("variance_frames"));
    for (size_t p = 0; p < g.pixel_count(); ++p) {
      if (!g.covered(p)) continue;
      shortened += it->second[p] < full - 0.5 ? 1.0 : 0.0;
      below_variance += it->second[p] < frames ? 1.0 : 0.0;
      counted += 1.0;
    }
  };

  // One sequence: per frame, its wall time around run() and its passes.
  auto sequence = [&](std::vector<double>& totals, std::vector<PassTimes>& passes) {
    std::unique_ptr<Estimator> est = e.create(params);
    for (int k = 0; k < o.frames; ++k) {
      const FrameInfo info{
          .index = k, .count = o.frames, .fps = 30.0, .seed_offset = static_cast<uint64_t>(k)};
      const EstimateContext context{scene, es, g, &info};
      est->prepare(context);
      const auto t0 = std::chrono::steady_clock::now();
      const EstimateResult r = est->run(context);
      totals.push_back(ms_since(t0));
      passes.push_back(r.pass_ms);
      count_histories(r, k);
    }
  };
  for (int i = 0; i < o.warmup; ++i) {
    std::vector<double> t;
    std::vector<PassTimes> p;
    sequence(t, p);
  }
  // Frame 0 of each timed sequence, and the steady frames 1..F-1 of all of them.
  std::vector<double> first_totals, steady_totals;
  std::vector<PassTimes> first_runs, steady_runs;
  for (int rep = 0; rep < o.repetitions; ++rep) {
    std::vector<double> totals;
    std::vector<PassTimes> runs;
    sequence(totals, runs);
    first_totals.push_back(totals.front());
    first_runs.push_back(runs.front());
    steady_totals.insert(steady_totals.end(), totals.begin() + 1, totals.end());
    steady_runs.insert(steady_runs.end(), runs.begin() + 1, runs.end());
  }
  const PassTimes steady = pass_medians(steady_runs);
  const PassTimes first = pass_medians(first_runs);

  // rtao's passes in pipeline order, then whatever else the estimator reports (gtao's).
  std::vector<std::string> order;
  if (rtao) {
    order = {"rays_ms", "temporal_ms", "variance_ms"};
    const int iterations = static_cast<int>(params.integer("atrous_iterations"));
    for (int i = 0; i < iterations; ++i) order.push_back("atrous_" + std::to_string(i) + "_ms");
    order.push_back("atrous_ms");
  }
  for (const auto& [pass, ms] : steady)
    if (std::find(order.begin(), order.end(), pass) == order.end()) order.push_back(pass);
  std::ostringstream md, csv;
  md << e.name << " (" << overrides.dump() << ") on " << scene.name << "/" << view.name << " ("
     << scene.triangle_count() << " triangles), " << w << "x" << h << " (" << covered
     << " covered pixels), " << o.frames << " frames of a static camera, device "
     << backend_device(e.backend) << "; medians over " << o.repetitions
     << " sequences (frame 0) and their frames 1.." << o.frames - 1 << " (steady), after "
     << o.warmup << " untimed\n\n"
     << "| pass | frame 0 ms | steady ms |\n|---|---:|---:|\n";
  csv << "pass,frame0_ms,steady_ms\n";
  char buf[256];
  for (const std::string& pass : order) {
    std::snprintf(buf, sizeof(buf), "| %s | %.2f | %.2f |\n", pass.c_str(), pass_ms(first, pass),
                  pass_ms(steady, pass));
    md << buf;
    csv << pass << ',' << pass_ms(first, pass) << ',' << pass_ms(steady, pass) << '\n';
  }
  const double steady_total = median(steady_totals), first_total = median(first_totals);
  std::snprintf(buf, sizeof(buf), "| total (wall) | %.2f | %.2f |\n", first_total, steady_total);
  md << buf;
  csv << "total," << first_total << ',' << steady_total << '\n';
  if (rtao) {
    // The denoiser's cost against the rays', both medians over the same steady frames: the
    // median of each frame's temporal + variance + a-trous, and the median of its rays.
    std::vector<double> denoiser;
    for (const PassTimes& frame : steady_runs)
      denoiser.push_back(pass_ms(frame, "temporal_ms") + pass_ms(frame, "variance_ms") +
                         pass_ms(frame, "atrous_ms"));
    const double denoiser_ms = median(denoiser), rays_ms = pass_ms(steady, "rays_ms");
    md << "\n- rays: " << format_number("%.1f", covered * params.integer("rays") / (rays_ms * 1e3))
       << " Mrays/s; denoiser (temporal + variance + a-trous): "
       << format_number("%.2f", denoiser_ms) << " ms a frame (median), "
       << format_number("%.2f", denoiser_ms / rays_ms) << " x the rays' "
       << format_number("%.2f", rays_ms) << " ms\n";
    csv << "denoiser,," << denoiser_ms << '\n';
    if (counted > 0.0)
      md << "- histories over the steady frames: "
         << format_number("%.3f", 100.0 * shortened / counted)
         << " % of covered pixels shorter than the frames allow (the anti-lag), "
         << format_number("%.3f", 100.0 * below_variance / counted)
         << " % below variance_frames (the variance's spatial estimate)\n";
  }
  std::printf("%s", md.str().c_str());

  // Bench writes its row once, at the end, and takes no lock on its folder.
  RunRecorder recorder(o.out_dir, o.database, "bench " + e.name, FolderAccess::shared);
  recorder.register_run();
  recorder.record(timing_row(recorder.context(), e, params, overrides, scene.name, view.name, w, h,
                             steady_totals, steady, backend_device(e.backend)));
  const std::string stem = "bench_" + e.name;
  write_text((fs::path(o.out_dir) / (stem + ".md")).string(), md.str());
  write_text((fs::path(o.out_dir) / (stem + ".csv")).string(), csv.str());
  std::printf("%s\n", (fs::path(o.out_dir) / (stem + ".md")).string().c_str());
}

}  // namespace aoeval
