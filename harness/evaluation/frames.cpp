// The frames of a point, a still's one and a sequence's many (CONTRACT §10), run and scored alike:
// run_frames() gives each frame its scene and G-buffer (a sequence frame its own posed scene and
// G-buffer, with motion and disocclusion from frame k - 1), its references, its timed runs
// (run_timed(): repetitions for a still, one run for a sequence frame) and its scoring
// (score_frame(): against its own references; in a sequence also by harness/scoring/temporal.h).
//
// State and seeds: an estimator that keeps state (EstimatorInfo::keeps_state) is one instance for
// the whole sequence and reads the seed rule from EstimateContext::frame; any other is created
// afresh for every frame with its `seed` parameter + k (when it has one and the run does not say
// "seed_per_frame": false), so a built-in without a temporal design of its own flickers exactly
// as much as its per-frame noise makes it. A still warms up the instance it times; a sequence a
// throw-away instance on frame 0 (its kept instance's history starts at frame 0).
#include "harness/evaluation/frames.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "base/errors.h"
#include "base/summary.h"
#include "estimators/registry.h"
#include "harness/evaluation/background_lane.h"
#include "harness/evaluation/repetition_policy.h"
#include "harness/scoring/bent_metrics.h"
#include "harness/scoring/metrics.h"
#include "harness/scoring/side_by_side.h"
#include "references/reference_cache.h"

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

const std::vector<float>* channel(const EstimateResult& r, const std::string& name) {
  const auto it = r.extra_channels.find(name);
  return it == r.extra_channels.end() ? nullptr : &it->second;
}

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

void EvaluationSession::run_timed(Estimator& estimator, const EstimateContext& context,
                                  const std::function<bool(const std::vector<double>&)>& enough,
                                  std::vector<double>& times,
                                  std::map<std::string, std::vector<double>>& passes,
                                  EstimateResult& result) {
  if (before_timed_frames_) {
    const auto timer = stages_.time(StageTimes::kWaitingForBackground);
    before_timed_frames_();
  }
  struct AfterFrames {  // resumes the background work however the frames end
    const std::function<void()>& after;
    ~AfterFrames() {
      if (after) after();
    }
  } after_frames{after_timed_frames_};
  const auto timer = stages_.time(StageTimes::kEstimatorFrames);
  while (!enough(times)) {
    const auto t0 = std::chrono::steady_clock::now();
    result = estimator.run(context);
    const double wall = ms_since(t0);
    const auto total = result.pass_ms.find("total_ms");
    times.push_back(total != result.pass_ms.end() ? total->second : wall);
    for (const auto& [pass, ms] : result.pass_ms) passes[pass].push_back(ms);
  }
}

void EvaluationSession::run_frames(Measurement& m, bool seed_per_frame) {
  const EstimatorInfo& e = *m.estimator;
  const View& view = *m.view;
  const bool sequence = view.sequence.has_value();
  const int frames = view.frame_count(), w = m.width, h = m.height;
  const SceneData& base = scenes_.scene(m.scene);
  const AoDefinition definition = e.definition(m.params);
  const bool true_is_matched = definition.to_json() == true_ao_definition().to_json();
  ResultRow& row = m.row;
  if (sequence) m.sequence = std::make_shared<SequenceScoring>();
  // Warm-up runs only where the first run pays for what later ones do not (EstimatorInfo::
  // warms_up()): a Vulkan estimator's first dispatch (pipeline and shader JIT in the driver, first
  // touch of its buffers) and a plug-in process, unless it declares its first run warm. A CPU or
  // Embree estimator is timed cold (issue 42): over 7 repetitions without warm-up (9 estimators x
  // 3 scenes, under load), a CPU or Embree estimator's first run was 0.88-1.24x the median of the
  // others, inside their own spread, and the median of all moved by 3 % at most (vertex-baked's
  // 0.05 ms frames aside, whose own spread is 70-180 %); a Vulkan one's first was up to 1.48x.
  const int warmup = e.warms_up() ? timing_.warmup : 0;

  std::vector<double> times, prepare_times;
  std::map<std::string, std::vector<double>> passes;
  std::unique_ptr<Estimator> kept;               // keeps_state: the one instance
  std::shared_ptr<const PosedFrame> prev_frame;  // a sequence's frame k - 1
  const std::vector<int> keep = sequence ? kept_sequence_frames(frames) : std::vector<int>{};
  // A sequence frame's references (truth: when it is not the matched one), shared with the frames'
  // scoring, and the frame they were traced for.
  std::shared_ptr<const ReferenceImage> matched, truth_owned;
  std::string matched_key, truth_key;  // their cache keys
  int prev_ref_frame = -1;
  size_t next_kept = 0;
  EstimateResult result;
  for (int k = 0; k < frames; ++k) {
    // The frame's scene and G-buffer: a still's are the caches'; a sequence frame's are posed and
    // rendered once for every point of the view (SceneCache::posed_frame()).
    std::shared_ptr<const PosedFrame> posed_frame;
    if (sequence) posed_frame = scenes_.posed_frame(m.scene, view, k, w, h, prev_frame.get());
    const SceneData& s = posed_frame && posed_frame->posed ? *posed_frame->posed : base;
    const Camera camera =
        sequence ? posed_frame->camera : scenes_.gbuffer(m.scene, view, w, h).camera;
    const std::shared_ptr<const GBuffer> frame_g =
        sequence ? posed_frame->gbuffer : std::shared_ptr<const GBuffer>();
    const GBuffer& g = sequence ? *frame_g : scenes_.gbuffer(m.scene, view, w, h);
    const FrameInfo info{.index = k,
                         .count = frames,
                         .fps = sequence ? view.sequence->fps : 0.0,
                         .seed_offset = seed_per_frame ? static_cast<uint64_t>(k) : 0};
    const EstimateContext context{s.scene, *s.embree, g, sequence ? &info : nullptr};
    const ParamSet params = e.keeps_state ? m.params : frame_params(e, m.params, info.seed_offset);
    if (sequence && k == 0 && warmup > 0) {
      const auto timer = stages_.time(StageTimes::kEstimatorWarmup);
      std::unique_ptr<Estimator> warm = e.create(params);
      warm->prepare(context);
      for (int i = 0; i < warmup; ++i) warm->run(context);
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
    if (!sequence) {
      const auto timer = stages_.time(StageTimes::kEstimatorWarmup);
      for (int i = 0; i < warmup; ++i) result = estimator.run(context);
    }

    // The frame's references, before its timed runs and on this thread, not on a background lane
    // where a trace would run for seconds beside the estimators' frames (after the warm-up, so
    // that an estimator without its backend traces none). A still's are kept by the store and
    // read when it is scored. A sequence frame's are cached per frame (its geometry, camera and
    // seed + j); one that poses what frame k - 1 did has frame k - 1's (j is the first frame of
    // the unchanged run, reference_frame()): traced once, kept from the last frame.
    const int ref_frame = scenes_.reference_frame(m.scene, view, k);
    const bool repeats = sequence && k > 0 && ref_frame == prev_ref_frame;
    if (!sequence) {
      references_.compute_missing(m.scene, view, w, h, definition);
      references_.compute_missing(m.scene, view, w, h, true_ao_definition());
    } else if (!repeats) {
      const std::vector<AoDefinition> companions =
          references_.planned_definitions(m.scene, view, w, h);
      const ReferenceSettings matched_settings = frame_settings(m.scene, view, k, definition);
      matched = std::make_shared<const ReferenceImage>(
          references_.frame_reference(s, view, camera, g, matched_settings, companions));
      matched_key = truth_key = reference_cache_key(s.content_hash, camera, matched_settings);
      truth_owned.reset();
      if (!true_is_matched) {
        const ReferenceSettings true_settings =
            frame_settings(m.scene, view, k, true_ao_definition());
        truth_owned = std::make_shared<const ReferenceImage>(
            references_.frame_reference(s, view, camera, g, true_settings, companions));
        truth_key = reference_cache_key(s.content_hash, camera, true_settings);
      }
    }
    prev_ref_frame = ref_frame;

    const size_t runs = times.size() + 1;  // a sequence frame: one timed run
    run_timed(
        estimator, context,
        [&](const std::vector<double>& t) {
          return sequence ? t.size() >= runs : enough_repetitions(timing_, t);
        },
        times, passes, result);
    if (result.ao.size() != g.pixel_count())
      throw std::runtime_error("estimator " + e.name + " returned " +
                               std::to_string(result.ao.size()) + " values for " +
                               std::to_string(g.pixel_count()) + " pixels" +
                               (sequence ? " (frame " + std::to_string(k) + ")" : ""));
    if (k == 0)
      row.timing_source = !result.timing_source.empty()           ? result.timing_source
                          : result.pass_ms.count("total_ms") != 0 ? "gpu-timestamps"
                                                                  : "wall";
    if (!sequence) break;  // scored by score() against the store's references

    if (next_kept < keep.size() && keep[next_kept] == k) {  // for the report (kept_sequence.h)
      const auto timer = stages_.time("estimate EXR");
      KeptFrame kf;
      kf.frame = k;
      kf.estimate = estimate_to_image(g, result);
      kf.attributes =
          estimate_attributes(s.scene, s.content_hash, view, camera, e, params, m.derived);
      kf.attributes.emplace_back("aoeval:frame", std::to_string(k));
      if (references_.disk_cache())
        kf.reference_cache = reference_cache_path(reference_cache_key(
            s.content_hash, camera, frame_settings(m.scene, view, k, definition)));
      m.kept_frames.push_back(std::move(kf));
      ++next_kept;
    }
    FrameToScore frame{.index = k,
                       .gbuffer = &g,
                       .estimate = &result,
                       .matched_key = matched_key,
                       .truth_key = truth_key,
                       .time_ms = times.back(),
                       .ref_repeats_previous = repeats,
                       .prev_jitter = k > 0 ? prev_frame->gbuffer->camera.jitter : glm::vec2(0.0f),
                       .last = k == frames - 1};
    if (frame.last) {  // left to score(), with what it needs
      SequenceScoring& state = *m.sequence;
      state.gbuffer = frame_g;
      state.matched = matched;
      state.truth = truth_owned;
      state.frame = frame;
      break;
    }
    // Scored in frame order, on the background lane when the runner gives one (set_background):
    // the job shares the frame's G-buffer and references and owns its estimate.
    auto score_job = [this, state = m.sequence, gbuffer = frame_g,
                      estimate = std::make_shared<const EstimateResult>(std::move(result)),
                      matched_ref = matched, truth_ref = truth_owned, frame]() mutable {
      frame.gbuffer = gbuffer.get();
      frame.estimate = estimate.get();
      frame.matched = matched_ref.get();
      frame.truth = truth_ref ? truth_ref.get() : matched_ref.get();
      score_frame(state.get(), nullptr, frame);
    };
    if (background_) {
      // A full queue holds this thread until the lane has scored a frame: the lane's share of
      // the critical path, counted as waiting (it was outside every stage: 14 s of the quiet
      // cold default run's 220 s).
      const auto timer = stages_.time(StageTimes::kWaitingForBackground);
      background_(std::move(score_job));
    } else {
      score_job();
    }
    prev_frame = std::move(posed_frame);
  }
  // Scored at once, the frames but the last are the measurement's already; on a background lane
  // they are when score() has run.
  if (m.sequence && !background_) m.frames = std::exchange(m.sequence->frames, {});
  m.result = std::move(result);
  row.set_times(times);
  for (const auto& [pass, values] : passes)
    if (pass != "total_ms") row.pass_ms[pass] = median(values);
  row.precompute_ms = median(prepare_times);
}

void EvaluationSession::score_frame(SequenceScoring* sequence, ResultRow* row,
                                    const FrameToScore& f) {
  const GBuffer& g = *f.gbuffer;
  const EstimateResult& result = *f.estimate;
  const int w = g.width, h = g.height;
  // A still is also scored with bent vectors when the estimate has them.
  const auto bent = sequence
                        ? std::nullopt
                        : bent_of_channels(channel(result, "bent.X"), channel(result, "bent.Y"),
                                           channel(result, "bent.Z"));
  // Between the steps a background lane may hold this thread while an estimator's frames are
  // timed (BackgroundLane::checkpoint; a no-op on the runner's own thread): the metrics against
  // each reference, then the bent normals and the sequence's scorers, so that a pause waits for
  // one step, not a whole scoring (issue 16: the runner's waits for the lane).
  struct Scored {
    nlohmann::json metrics;
    std::vector<uint8_t> mask;
  };
  // The metrics against one reference: no stage timer and no checkpoint inside, so that it may run
  // on a thread of its own (side_by_side.h). A still scores with FLIP's reference side the store
  // keeps for its reference, a sequence frame with the one the store keeps for its reference's
  // cache key (shared by the view's points).
  auto metrics_against = [&](const ReferenceImage& ref, const std::string& key) {
    const flip::ReferenceSide* flip_side = nullptr;
    std::shared_ptr<const flip::ReferenceSide> frame_side;
    if (!sequence)
      flip_side = &references_.flip_reference(g, ref);
    else if (!key.empty())
      flip_side = (frame_side = references_.flip_frame_reference(key, g, ref)).get();
    Scored s;
    s.mask = compared_pixels(g, ref);
    s.metrics = to_json(compare_images({w, h, ref.ao.data()}, {w, h, result.ao.data()}, s.mask,
                                       ref.stderr_ao, flip_side),
                        "");
    return s;
  };
  // Then, in order: a still's bent normals, and the sequence's scorers this reference feeds (both
  // when it is matched and true).
  auto finish = [&](const ReferenceImage& ref, Scored& s, std::vector<TemporalScorer*> temporal) {
    const auto timer = stages_.time("scoring");
    if (bent)
      if (const auto b = compare_bent(w, h, ref.bent, *bent, s.mask, ref.bent_stderr))
        add_bent_json(*b, s.metrics);
    if (!temporal.empty()) {
      const TemporalFrame frame =
          temporal_frame(w, h, result.ao.data(), ref.ao.data(), ref.stderr_ao, s.mask, &g,
                         f.prev_jitter, f.ref_repeats_previous);
      for (TemporalScorer* scorer : temporal) scorer->add_frame(frame);
    }
  };
  // An estimator whose declared definition is true AO is scored against one reference twice: the
  // same inputs give the same numbers, so the second scoring is the first's copy, and a
  // sequence's true-AO scorer takes the same frame as its matched one (issue 42: scoring each
  // frame once halved that cost for the sequences' constant and raytraced points).
  const bool one_reference = f.truth == f.matched;
  std::vector<TemporalScorer*> matched_scorers;
  if (sequence) {
    matched_scorers.push_back(&sequence->matched_scores);
    if (one_reference) matched_scorers.push_back(&sequence->true_scores);
  }
  Scored matched, truth;
  if (sequence && !one_reference) {
    // A sequence frame's two scorings are independent and each mostly one thread (FLIP's
    // filters): side by side they take the time of one, which is what the runner waits for when
    // the lane falls behind over a sequence's frames (issue 42). The same bits in any schedule.
    // Only sequence frames: their FLIP sides are shared_ptrs the store may drop meanwhile.
    const auto timer = stages_.time("scoring");
    detail::side_by_side([&] { matched = metrics_against(*f.matched, f.matched_key); },
                         [&] { truth = metrics_against(*f.truth, f.truth_key); });
  } else {
    {
      const auto timer = stages_.time("scoring");
      matched = metrics_against(*f.matched, f.matched_key);
    }
    if (!one_reference) {
      BackgroundLane::checkpoint();
      const auto timer = stages_.time("scoring");
      truth = metrics_against(*f.truth, f.truth_key);
    }
  }
  BackgroundLane::checkpoint();
  finish(*f.matched, matched, matched_scorers);
  if (!one_reference)
    finish(*f.truth, truth,
           sequence ? std::vector<TemporalScorer*>{&sequence->true_scores}
                    : std::vector<TemporalScorer*>{});
  else
    truth = matched;
  const nlohmann::json& matched_json = matched.metrics;
  const nlohmann::json& truth_json = truth.metrics;
  BackgroundLane::checkpoint();
  if (sequence) {
    nlohmann::json frame_row = {{"frame", f.index}, {"time_ms", f.time_ms}};
    size_t disoccluded = 0;
    for (size_t p = 0; p < g.pixel_count(); ++p)
      disoccluded += g.covered(p) && g.disoccluded[p] > 0.5f;
    frame_row["disoccluded_pixels"] = disoccluded;
    frame_row.update(matched_json);
    for (const auto& [key, value] : truth_json.items()) frame_row["true_" + key] = value;
    sequence->frames.push_back(frame_row);
  }
  if (!f.last) return;
  row->metrics = matched_json;
  row->true_metrics = truth_json;
}

}  // namespace aoeval
