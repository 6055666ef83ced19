// The temporal runner (CONTRACT §10): a sequence point's frames run in order, each on its own
// posed scene and G-buffer (motion and disocclusion from frame k - 1), each timed once and scored
// against its own references; the scores of harness/scoring/temporal.h summarise them.
//
// State and seeds: an estimator that keeps state (EstimatorInfo::keeps_state) is one instance for
// the whole sequence and reads the seed rule from EstimateContext::frame; any other is created
// afresh for every frame with its `seed` parameter + k (when it has one and the run does not say
// "seed_per_frame": false), so a built-in without a temporal design of its own flickers exactly
// as much as its per-frame noise makes it. Warm-up runs use a throw-away instance on frame 0.
#include <algorithm>
#include <chrono>
#include <optional>

#include "base/errors.h"
#include "base/summary.h"
#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"
#include "harness/scoring/metrics.h"
#include "harness/scoring/temporal.h"
#include "references/reference_cache.h"
#include "scenes/sequence_frame.h"

namespace aoeval {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The parameters of frame k under the seed rule.
ParamSet frame_params(const EstimatorInfo& e, const ParamSet& params, uint64_t seed_offset) {
  const ParamSpec* seed = e.find_param("seed");
  if (!seed || seed->type != ParamType::integer || seed_offset == 0) return params;
  nlohmann::json values = params.json();
  values["seed"] = values["seed"].get<int64_t>() + static_cast<int64_t>(seed_offset);
  return resolve_params(e.name, e.params, values, "estimator " + e.name + " (frame seed)");
}

struct FrameScene {
  const EvaluationSession::SceneData* data = nullptr;
  std::optional<EvaluationSession::SceneData> owned;  // posed frames, dropped after their frame
};

}  // namespace

std::vector<int> kept_sequence_frames(int frames) {
  std::vector<int> kept;
  if (frames <= 0) return kept;
  const int n = std::min(frames, kMaxKeptFrames);
  if (n == 1) return {frames - 1};
  // k-th of n evenly spaced over 0..frames-1, rounded: distinct because frames - 1 >= n - 1.
  for (int k = 0; k < n; ++k)
    kept.push_back(
        static_cast<int>((static_cast<int64_t>(k) * (frames - 1) + (n - 1) / 2) / (n - 1)));
  return kept;
}

void EvaluationSession::measure_sequence(Measurement& m, bool seed_per_frame) {
  const EstimatorInfo& e = *m.estimator;
  const View& view = *m.view;
  const Sequence& seq = *view.sequence;
  const int w = m.width, h = m.height;
  const SceneData& base = scene(m.scene);
  const AoDefinition definition = e.definition(m.params);
  const bool true_is_matched = definition.to_json() == true_ao_definition().to_json();
  ResultRow& row = m.row;

  // Frame k's posed scene: the base scene when nothing moves; frames are posed one at a time so
  // that a long sequence holds two frames' geometry at most.
  auto pose = [&](const SequenceFrame& f) {
    FrameScene fs;
    if (!f.moves_objects) {
      fs.data = &base;
      return fs;
    }
    const auto timer = stages_.time("scene load + BVH");
    fs.owned.emplace();
    fs.owned->scene = posed_scene(base.scene, f);
    fs.owned->embree = std::make_unique<EmbreeScene>(fs.owned->scene);
    fs.owned->content_hash = fs.owned->scene.content_hash();
    fs.data = &*fs.owned;
    return fs;
  };

  TemporalScorer matched_scores, true_scores;
  std::vector<double> times, prepare_times;
  std::map<std::string, std::vector<double>> passes;
  std::unique_ptr<Estimator> kept;  // keeps_state: the one instance
  GBuffer prev_g;
  SequenceFrame prev_f;
  const std::vector<int> keep = kept_sequence_frames(seq.frames);
  ReferenceImage matched;                     // frame k's references ...
  std::optional<ReferenceImage> truth_owned;  // ... (truth: when it is not the matched one)
  int prev_ref_frame = -1;                    // ... and the frame they were traced for
  size_t next_kept = 0;
  try {
    for (int k = 0; k < seq.frames; ++k) {
      const SequenceFrame f = sequence_frame(base.scene, view, k);
      const FrameScene fs = pose(f);
      const SceneData& s = *fs.data;
      const Camera camera = frame_camera(f, w, h);
      GBuffer g;
      {
        const auto timer = stages_.time("G-buffer");
        g = render_gbuffer(*s.embree, camera);
        add_motion(g, k > 0 ? &prev_g : nullptr, f.motion, k > 0 ? prev_f.motion : f.motion);
      }
      const FrameInfo info{.index = k,
                           .count = seq.frames,
                           .fps = seq.fps,
                           .seed_offset = seed_per_frame ? static_cast<uint64_t>(k) : 0};
      const EstimateContext context{s.scene, *s.embree, g, &info};
      const ParamSet params =
          e.keeps_state ? m.params : frame_params(e, m.params, info.seed_offset);
      if (k == 0 && timing_.warmup > 0) {
        const auto timer = stages_.time(StageTimes::kEstimatorWarmup);
        std::unique_ptr<Estimator> warm = e.create(params);
        warm->prepare(context);
        for (int i = 0; i < timing_.warmup; ++i) warm->run(context);
      }
      std::unique_ptr<Estimator> fresh;
      if (!e.keeps_state || !kept) {
        const auto timer = stages_.time("estimator set-up");
        fresh = e.create(params);
      }
      Estimator& estimator = e.keeps_state ? *(kept ? kept : (kept = std::move(fresh))) : *fresh;
      const auto t_pre = std::chrono::steady_clock::now();
      estimator.prepare(context);
      prepare_times.push_back(ms_since(t_pre));
      stages_.add(StageTimes::kEstimatorPrecompute, prepare_times.back());
      if (k == 0) {
        m.derived = estimator.derived();
        if (!m.derived.empty()) row.params["derived"] = m.derived;
      }
      EstimateResult result;
      {
        if (before_timed_frames_) before_timed_frames_();
        struct AfterFrames {
          const std::function<void()>& after;
          ~AfterFrames() {
            if (after) after();
          }
        } after_frames{after_timed_frames_};
        const auto timer = stages_.time(StageTimes::kEstimatorFrames);
        const auto t0 = std::chrono::steady_clock::now();
        result = estimator.run(context);
        const double wall = ms_since(t0);
        const auto total = result.pass_ms.find("total_ms");
        times.push_back(total != result.pass_ms.end() ? total->second : wall);
        for (const auto& [pass, ms] : result.pass_ms) passes[pass].push_back(ms);
      }
      if (result.ao.size() != g.pixel_count())
        throw std::runtime_error("estimator " + e.name + " returned " +
                                 std::to_string(result.ao.size()) + " values for " +
                                 std::to_string(g.pixel_count()) + " pixels (frame " +
                                 std::to_string(k) + ")");
      if (k == 0)
        row.timing_source = !result.timing_source.empty()           ? result.timing_source
                            : result.pass_ms.count("total_ms") != 0 ? "gpu-timestamps"
                                                                    : "wall";

      // Scoring: this frame's references (cached per frame: its geometry, camera and seed + j).
      // A frame that poses what frame k - 1 did has frame k - 1's references (j is the first
      // frame of the unchanged run, reference_frame()): traced once, kept from the last frame.
      const int ref_frame = reference_frame(m.scene, view, k);
      const bool repeats = k > 0 && ref_frame == prev_ref_frame;
      if (!repeats) {
        const std::vector<AoDefinition> companions = planned_definitions(m.scene, view, w, h);
        matched = reference_image(s, view, camera, g, frame_settings(m.scene, view, k, definition),
                                  companions);
        truth_owned.reset();
        if (!true_is_matched)
          truth_owned =
              reference_image(s, view, camera, g,
                              frame_settings(m.scene, view, k, true_ao_definition()), companions);
      }
      prev_ref_frame = ref_frame;
      const ReferenceImage& truth = truth_owned ? *truth_owned : matched;
      if (next_kept < keep.size() && keep[next_kept] == k) {  // for the report (kept_sequence.h)
        const auto timer = stages_.time("estimate EXR");
        KeptFrame kf;
        kf.frame = k;
        kf.estimate = estimate_to_image(g, result);
        kf.attributes =
            estimate_attributes(s.scene, s.content_hash, view, camera, e, params, m.derived);
        kf.attributes.emplace_back("aoeval:frame", std::to_string(k));
        if (disk_cache_)
          kf.reference_cache = reference_cache_path(reference_cache_key(
              s.content_hash, camera, frame_settings(m.scene, view, k, definition)));
        m.kept_frames.push_back(std::move(kf));
        ++next_kept;
      }
      const auto timer = stages_.time("scoring");
      nlohmann::json frame_row = {{"frame", k}, {"time_ms", times.back()}};
      size_t disoccluded = 0;
      for (size_t p = 0; p < g.pixel_count(); ++p)
        disoccluded += g.covered(p) && g.disoccluded[p] > 0.5f;
      frame_row["disoccluded_pixels"] = disoccluded;
      auto score_frame = [&](const ReferenceImage& ref, TemporalScorer& scorer,
                             const std::string& prefix) {
        std::vector<uint8_t> mask(g.pixel_count());
        for (size_t p = 0; p < mask.size(); ++p) mask[p] = g.covered(p) && ref.covered(p);
        const Metrics metrics =
            compare_images({w, h, ref.ao.data()}, {w, h, result.ao.data()}, mask, ref.stderr_ao);
        TemporalFrame tf;
        tf.width = w;
        tf.height = h;
        tf.est = result.ao.data();
        tf.ref = ref.ao.data();
        tf.ref_stderr = ref.stderr_ao.empty() ? nullptr : ref.stderr_ao.data();
        tf.compared = mask.data();
        tf.motion = &g.motion[0].x;
        tf.disoccluded = g.disoccluded.data();
        tf.prev_jitter_x = k > 0 ? prev_g.camera.jitter.x : 0.0f;
        tf.prev_jitter_y = k > 0 ? prev_g.camera.jitter.y : 0.0f;
        tf.ref_repeats_previous = repeats;
        scorer.add_frame(tf);
        frame_row.update(to_json(metrics, prefix));
        return to_json(metrics, prefix);
      };
      const nlohmann::json last_matched = score_frame(matched, matched_scores, "");
      const nlohmann::json last_true = score_frame(truth, true_scores, "true_");
      m.frames.push_back(frame_row);
      if (k == seq.frames - 1) {  // the row's plain keys are the last frame's (still_frame())
        row.metrics = last_matched;
        nlohmann::json t;
        for (const auto& [key, value] : last_true.items()) t[key.substr(5)] = value;
        row.true_metrics = t;
        m.result = std::move(result);
      }
      prev_g = std::move(g);
      prev_f = f;
    }
  } catch (const EstimatorUnavailable& unavailable) {
    row.status = std::string("skipped: ") + unavailable.what();
    row.timestamp = utc_now();
    m.result = EstimateResult{};
    m.frames.clear();
    m.kept_frames.clear();
    return;
  }
  m.rmse_excess_by_age = matched_scores.rmse_excess_by_age();
  m.settle_excess_by_age = matched_scores.settle_excess_by_age();
  m.flicker_map = matched_scores.flicker_map();
  m.lag_map = matched_scores.lag_map();
  row.metrics.update(matched_scores.scores());
  row.true_metrics.update(true_scores.scores());
  row.set_times(times);
  for (const auto& [pass, values] : passes)
    if (pass != "total_ms") row.pass_ms[pass] = median(values);
  row.precompute_ms = median(prepare_times);
  row.timestamp = utc_now();
  m.scored = true;
}

}  // namespace aoeval
