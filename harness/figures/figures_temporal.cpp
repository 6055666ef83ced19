// `rtao-convergence` (ours, issue 31): see figures_temporal.h.
#include "harness/figures/figures_temporal.h"

#include <cmath>

#include "estimators/registry.h"
#include "harness/figures/figure_util.h"

namespace aoeval::figures {

int first_frame_staying_below(const std::vector<double>& curve, double level) {
  int first = -1;
  for (size_t k = 0; k < curve.size(); ++k) {
    if (curve[k] <= level) {
      if (first < 0) first = static_cast<int>(k);
    } else {
      first = -1;
    }
  }
  return first;
}

double steady_of(const std::vector<double>& curve) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t k = curve.size() / 2; k < curve.size(); ++k, ++n) sum += curve[k] * curve[k];
  return n ? std::sqrt(sum / static_cast<double>(n)) : std::nan("");
}

std::vector<Check> rtao_convergence_checks(const ConvergenceNumbers& n) {
  std::vector<Check> checks;
  {
    Check c{
        "rtao at 1 ray per pixel reaches raytraced at 16 rays per frame (its steady "
        "rmse_excess) and stays there before the sequence ends",
        false, "raytraced 16 rays: not measured"};
    if (const auto it = n.raytraced.find(16); it != n.raytraced.end() && !n.rtao.empty()) {
      const double level = steady_of(it->second);
      const int f = first_frame_staying_below(n.rtao, level);
      c.passed = f >= 0;
      c.measured = "raytraced 16 rays steady " + fmt(level) + "; rtao from frame " +
                   (f >= 0 ? std::to_string(f) : std::string("never")) + " of " +
                   std::to_string(n.rtao.size()) + " (its steady " + fmt(n.rtao_steady) + ")";
    }
    checks.push_back(c);
  }
  checks.push_back({"the a-trous passes lower rtao's steady_rmse_excess (with < without)",
                    n.rtao_steady < n.no_atrous_steady,
                    "with " + fmt(n.rtao_steady) + ", without " + fmt(n.no_atrous_steady)});
  const bool settled = std::isfinite(n.settle_frames);
  checks.push_back({"after a disocclusion rtao settles (settle_frames) within " +
                        std::to_string(kSettleFramesBound) + " frames",
                    settled && n.settle_frames <= kSettleFramesBound,
                    settled ? fmt(n.settle_frames) + " frames"
                            : "never settled within the " +
                                  std::to_string(n.settle_sequence_frames) + "-frame sequence"});
  return checks;
}

std::vector<Check> gtao_temporal_checks(const GtaoTemporalNumbers& n) {
  const double acc = steady_of(n.accumulated), six = steady_of(n.six_slices);
  const int f = first_frame_staying_below(n.accumulated, kApproachFactor * six);
  return {
      {"1 slice with 6 rotations, accumulated, approaches 6 slices per frame: steady "
       "rmse_excess within " +
           fmt(kApproachFactor, 3) + " x",
       acc <= kApproachFactor * six,
       "accumulated " + fmt(acc) +
           " (frame 0: " + fmt(n.accumulated.empty() ? std::nan("") : n.accumulated.front()) +
           "), 6 slices " + fmt(six) + " (" + fmt(acc / six, 3) +
           " x); both include GTAO's own bias against "
           "ray-traced AO"},
      {"it gets there within the 6 rotations (frames 0..5) and stays", f >= 0 && f <= 5,
       f >= 0 ? "from frame " + std::to_string(f) : std::string("never")},
      {"its per-frame cost is below 6 slices per frame", n.accumulated_ms < n.six_slices_ms,
       fmt(n.accumulated_ms) + " ms against " + fmt(n.six_slices_ms) + " ms (median per frame)"},
  };
}

std::string winner_by(const std::vector<EqualTimeContender>& c, double EqualTimeContender::*key) {
  const EqualTimeContender* best = nullptr;
  for (const auto& e : c)
    if (std::isfinite(e.*key) && (!best || e.*key < best->*key)) best = &e;
  return best ? best->name : "";
}

std::vector<Check> temporal_equal_time_checks(const TemporalEqualTimeNumbers& n) {
  std::vector<Check> checks;
  std::string times;
  bool held = !n.contenders.empty();
  for (const auto& c : n.contenders) {
    held = held && c.ms <= 1.5 * n.budget_ms;
    times += (times.empty() ? "" : ", ") + c.name + " " + fmt(c.ms, 3) + " ms";
  }
  checks.push_back({"equal time held: every contender's median frame time within 1.5 x the budget",
                    held, "budget " + fmt(n.budget_ms, 3) + " ms: " + times});
  const std::string steady = winner_by(n.contenders, &EqualTimeContender::steady);
  const std::string flicker = winner_by(n.contenders, &EqualTimeContender::flicker);
  const std::string settle = winner_by(n.contenders, &EqualTimeContender::settle);
  checks.push_back(
      {"which estimator wins depends on the question: the winners by "
       "steady_rmse_excess, temporal_rmse_excess and settle_frames are not all one",
       !steady.empty() && !(steady == flicker && flicker == settle),
       "steady: " + steady + "; flicker: " + flicker + "; settle: " + settle});
  return checks;
}

namespace {

struct SequenceRun {
  std::vector<double> by_frame;
  ResultRow row;
};

SequenceRun run_sequence(FigureContext& ctx, const std::string& estimator,
                         const nlohmann::json& overrides, const std::string& scene,
                         const std::string& view, int w, int h) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = overrides;
  req.scene = scene;
  req.view = view;
  req.width = w;
  req.height = h;
  Measurement m = ctx.session->measure(req);
  SequenceRun s;
  s.row = ctx.session->score(m);
  for (const auto& f : m.frames) s.by_frame.push_back(f.value("rmse_excess", std::nan("")));
  return s;
}

double metric(const ResultRow& row, const char* key) {
  const auto it = row.metrics.find(key);
  return it != row.metrics.end() && it->is_number() ? it->get<double>() : std::nan("");
}

FigureResult rtao_convergence(FigureContext& ctx) {
  const int long_side = ctx.pick(160, 48);
  FigureResult r;
  ConvergenceNumbers n;
  r.table.columns = {"series", "scene", "view", "frame", "rmse_excess"};
  PlotSpec plot;
  plot.title = "rmse_excess by frame, bunny/still (static camera)";
  plot.x_label = "frame";
  plot.y_label = "rmse_excess";
  plot.log_y = true;
  const std::string scene = "bunny", view = "still";
  const auto [w, h] = view_size(ctx, scene, view, long_side);
  auto add = [&](const std::string& label, const std::vector<double>& curve) {
    PlotSeries s = make_series(label);
    for (size_t k = 0; k < curve.size(); ++k) {
      s.x.push_back(static_cast<double>(k));
      s.y.push_back(curve[k]);
      r.table.add({label, scene, view, std::to_string(k), fmt(curve[k])});
    }
    plot.series.push_back(s);
  };
  const SequenceRun rtao = run_sequence(ctx, "rtao", {{"rays", 1}}, scene, view, w, h);
  const SequenceRun plain =
      run_sequence(ctx, "rtao", {{"rays", 1}, {"atrous_iterations", 0}}, scene, view, w, h);
  n.rtao = rtao.by_frame;
  n.rtao_no_atrous = plain.by_frame;
  n.rtao_steady = metric(rtao.row, "steady_rmse_excess");
  n.no_atrous_steady = metric(plain.row, "steady_rmse_excess");
  add("rtao 1 ray", n.rtao);
  add("rtao 1 ray, no a-trous", n.rtao_no_atrous);
  for (int rays : {1, 4, 16, 64}) {
    const SequenceRun rt = run_sequence(ctx, "raytraced", {{"rays", rays}}, scene, view, w, h);
    n.raytraced[rays] = rt.by_frame;
    add("raytraced " + std::to_string(rays) + " rays/frame", rt.by_frame);
  }
  // Disocclusion: the dragon crossing the floor.
  const std::string dscene = "dragon", dview = "walk";
  const auto [dw, dh] = view_size(ctx, dscene, dview, ctx.pick(128, 40));
  const SequenceRun walk = run_sequence(ctx, "rtao", {{"rays", 1}}, dscene, dview, dw, dh);
  n.settle_frames = metric(walk.row, "settle_frames");
  n.settle_sequence_frames = static_cast<int>(walk.by_frame.size());
  for (size_t k = 0; k < walk.by_frame.size(); ++k)
    r.table.add({"rtao 1 ray", dscene, dview, std::to_string(k), fmt(walk.by_frame[k])});
  render_plot(plot, ctx.path("rtao-convergence.png"));
  r.images = {"rtao-convergence.png"};
  r.checks = rtao_convergence_checks(n);
  r.measured = "bunny/still (16 frames, static camera) at " + std::to_string(w) + "x" +
               std::to_string(h) +
               ": rtao at its defaults with 1 ray per pixel per frame, with "
               "and without its a-trous passes, and raytraced at 1, 4, 16, 64 rays per frame "
               "(fresh rays each frame, no accumulation); dragon/walk at " +
               std::to_string(dw) + "x" + std::to_string(dh) +
               " for rtao's settle_frames (disocclusion_rmse_excess " +
               fmt(metric(walk.row, "disocclusion_rmse_excess")) +
               "); rmse_excess against each frame's reference (" +
               std::to_string(ctx.session->reference_spec().spp) + " spp, its noise removed)";
  return r;
}

FigureResult gtao_temporal(FigureContext& ctx) {
  const std::string scene = "bunny", view = "still";
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(320, 48));
  FigureResult r;
  r.table.columns = {"series", "frame", "rmse_excess"};
  PlotSpec plot;
  plot.title = "gtao-cpu on bunny/still (static camera): rmse_excess by frame";
  plot.x_label = "frame";
  plot.y_label = "rmse_excess";
  GtaoTemporalNumbers n;
  const nlohmann::json one = {{"slices", 1}, {"rotations", 6}, {"temporal", true}};
  const nlohmann::json six = {{"slices", 6}};
  const SequenceRun a = run_sequence(ctx, "gtao-cpu", one, scene, view, w, h);
  const SequenceRun b = run_sequence(ctx, "gtao-cpu", six, scene, view, w, h);
  n.accumulated = a.by_frame;
  n.six_slices = b.by_frame;
  n.accumulated_ms = a.row.time_ms_median;
  n.six_slices_ms = b.row.time_ms_median;
  for (const auto& [label, curve] :
       {std::pair{std::string("1 slice, 6 rotations, temporal stage"), n.accumulated},
        std::pair{std::string("6 slices per frame"), n.six_slices}}) {
    PlotSeries s = make_series(label);
    for (size_t k = 0; k < curve.size(); ++k) {
      s.x.push_back(static_cast<double>(k));
      s.y.push_back(curve[k]);
      r.table.add({label, std::to_string(k), fmt(curve[k])});
    }
    plot.series.push_back(s);
  }
  render_plot(plot, ctx.path("gtao-temporal.png"));
  r.images = {"gtao-temporal.png"};
  r.checks = gtao_temporal_checks(n);
  r.measured =
      "gtao-cpu (the same bits as gtao) at its defaults on bunny/still (16 frames, static "
      "camera) at " +
      std::to_string(w) + "x" + std::to_string(h) +
      ": slices 1, rotations 6, temporal true (the shared stage at gtao's defaults) "
      "against slices 6 per frame; rmse_excess against each frame's reference (" +
      std::to_string(ctx.session->reference_spec().spp) +
      " spp), frame times the harness's median over frames (2 shared cores)";
  return r;
}

FigureResult temporal_equal_time(FigureContext& ctx) {
  const std::string scene = "dragon", view = "walk";
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(128, 40));
  const int warmup = 1, reps = ctx.quick ? 3 : 7;
  FigureResult r;
  TemporalEqualTimeNumbers n;
  r.table.columns = {
      "contender",    "overrides", "frame_ms", "steady_rmse_excess", "temporal_rmse_excess",
      "settle_frames"};
  auto add = [&](const std::string& name, const std::string& estimator,
                 const nlohmann::json& overrides) {
    const SequenceRun run = run_sequence(ctx, estimator, overrides, scene, view, w, h);
    EqualTimeContender c{name, metric(run.row, "steady_rmse_excess"),
                         metric(run.row, "temporal_rmse_excess"), metric(run.row, "settle_frames"),
                         run.row.time_ms_median};
    n.contenders.push_back(c);
    r.table.add({name, overrides.dump(), fmt(c.ms), fmt(c.steady), fmt(c.flicker), fmt(c.settle)});
    return c;
  };
  // The budget: rtao at its defaults, 1 ray per pixel per frame.
  n.budget_ms = add("rtao", "rtao", {{"rays", 1}}).ms;
  // Each other contender at the dearest point of its ladder whose still-frame time (interleaving
  // is not needed here: one point per contender) is within the budget.
  auto dearest = [&](const std::string& estimator, const std::string& knob,
                     const std::vector<int>& ladder, nlohmann::json fixed) {
    int chosen = ladder.front();
    for (int v : ladder) {
      nlohmann::json o = fixed;
      o[knob] = v;
      if (time_estimator(ctx, estimator, o, scene, view, w, h, warmup, reps).median_ms <=
          n.budget_ms)
        chosen = v;
      else
        break;
    }
    fixed[knob] = chosen;
    return fixed;
  };
  const nlohmann::json rt =
      dearest("raytraced", "rays", {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64}, {});
  add("raytraced rays:" + rt["rays"].dump(), "raytraced", rt);
  const nlohmann::json gt = dearest("gtao-cpu", "slices", {1, 2, 3, 4, 6, 8, 12, 16},
                                    {{"rotations", 6}, {"temporal", true}});
  add("gtao-cpu temporal slices:" + gt["slices"].dump(), "gtao-cpu", gt);
  const nlohmann::json gp = dearest("gtao-cpu", "slices", {1, 2, 3, 4, 6, 8, 12, 16}, {});
  add("gtao-cpu per frame slices:" + gp["slices"].dump(), "gtao-cpu", gp);

  PlotSpec plot;
  plot.title = "dragon/walk at rtao's frame time: three questions";
  plot.y_label = "value (lower is better)";
  for (const auto& c : n.contenders) plot.categories.push_back(c.name);
  for (const auto& [label, key] :
       {std::pair{std::string("steady_rmse_excess"), &EqualTimeContender::steady},
        std::pair{std::string("temporal_rmse_excess"), &EqualTimeContender::flicker}}) {
    PlotSeries s = make_series(label, "bar");
    for (size_t i = 0; i < n.contenders.size(); ++i) {
      s.x.push_back(static_cast<double>(i));
      s.y.push_back(n.contenders[i].*key);
    }
    plot.series.push_back(s);
  }
  render_plot(plot, ctx.path("temporal-equal-time.png"));
  r.images = {"temporal-equal-time.png"};
  r.checks = temporal_equal_time_checks(n);
  r.measured =
      "dragon/walk (48 frames, the dragon crossing the floor: motion and disocclusions) "
      "at " +
      std::to_string(w) + "x" + std::to_string(h) +
      "; budget = rtao's median frame time at its defaults (1 ray per pixel); raytraced "
      "(rays) and gtao-cpu (slices; with rotations 6 and its temporal stage, and per "
      "frame) at the dearest point of their ladders whose still-frame median time (" +
      std::to_string(reps) +
      " runs) is within it; scored against each frame's "
      "reference (" +
      std::to_string(ctx.session->reference_spec().spp) + " spp). Winners per question: steady " +
      winner_by(n.contenders, &EqualTimeContender::steady) + ", flicker " +
      winner_by(n.contenders, &EqualTimeContender::flicker) + ", settle " +
      winner_by(n.contenders, &EqualTimeContender::settle) +
      " (settle_frames blank = never settled, ranked last)";
  return r;
}

}  // namespace

std::vector<Figure> temporal_figures() {
  return {
      {"gtao-temporal", "Jimenez et al. 2016, §5.2 (temporal rotations and reprojection)",
       "GTAO with one slice per pixel per frame and 6 temporal rotations, accumulated by temporal "
       "reprojection, gives the quality of 6 slices per frame at the cost of one.",
       gtao_temporal},
      {"rtao-convergence", "ours (SVGF-style real-time ray-traced AO, Schied et al. 2017)",
       "One ray per pixel per frame, accumulated over time with a per-frame advancing sequence and "
       "denoised with a-trous passes, soon beats many rays per frame without accumulation, and "
       "settles within a few frames after a disocclusion.",
       rtao_convergence},
      {"temporal-equal-time", "ours (the equal-time comparison over sequences)",
       "At equal time per frame, which estimator wins depends on the question: the lowest steady "
       "error, the least flicker and the fastest recovery after a disocclusion need not be one "
       "estimator.",
       temporal_equal_time},
  };
}

}  // namespace aoeval::figures
