// One evaluation = an estimator with its parameters on one scene view at one resolution: run it
// (precompute, warm-up, timed repetitions), score it against the reference of its own AO definition
// ("matched") and against true AO, and return a results row. The session caches what runs share:
// scenes, Embree scenes, G-buffers and references (in memory, and references on disk too).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>

#include "estimators/estimator.h"
#include "harness/results/result_row.h"
#include "harness/results/stage_times.h"
#include "harness/scoring/flip.h"
#include "references/reference.h"

namespace aoeval {

// The reference of a sweep or suite; its defaults are ReferenceSettings' (references/reference.h).
struct ReferenceSpec {
  int spp = ReferenceSettings{}.spp;
  SamplerKind sampler = ReferenceSettings{}.sampler;
  uint64_t seed = ReferenceSettings{}.seed;
  nlohmann::json to_json() const;
  // The reference's settings for one AO definition.
  ReferenceSettings settings(const AoDefinition& definition) const;
};

struct TimingSpec {
  int warmup = 1;
  int repetitions = 5;  // fixed, or the least when max_repetitions is larger (repetition_policy.h)
  int max_repetitions = 0;
  double median_ci = 0.05;
};

struct EvaluationRequest {
  const EstimatorInfo* estimator = nullptr;
  nlohmann::json overrides = nlohmann::json::object();  // the parameters set explicitly
  std::string scene, view;                              // view "" = the scene's first
  int width = 0, height = 0;                            // 0 = the view's own
  // Sequence views (CONTRACT §10): frame k runs with seed + k unless the run says false.
  bool seed_per_frame = true;
};

// "raytraced/rays:16/scene:bunny/view:main/640x480": the explicitly set parameters in declaration
// order, then scene, view and resolution.
std::string run_name(const EstimatorInfo& e, const ParamSet& params,
                     const nlohmann::json& overrides, const std::string& scene,
                     const std::string& view, int width, int height);

// The frames a sequence point keeps for its report (strip, video, viewer; CONTRACT §10): every
// frame up to kMaxKeptFrames, else that many evenly spaced, first and last included, so a point
// keeps at most kMaxKeptFrames times what a still point keeps, however long the sequence.
inline constexpr int kMaxKeptFrames = 48;
std::vector<int> kept_sequence_frames(int frames);

// One kept frame: its estimate image (AO, A and extra channels, as the row's estimate EXR) with
// its header, and the matched reference's cache entry it was scored against ("" without a disk
// cache). The runners write them under the point's folder (harness/sweep/kept_sequence.h).
struct KeptFrame {
  int frame = 0;
  OIIO::ImageBuf estimate;
  Attributes attributes;
  std::string reference_cache;
};

// What an evaluation measured before it is scored: the row so far (identity, timings, status),
// the last frame's estimate and what scoring needs to find its references.
struct Measurement {
  ResultRow row;
  EstimateResult result;
  const EstimatorInfo* estimator = nullptr;
  ParamSet params;
  nlohmann::json derived;
  std::string scene;
  const View* view = nullptr;
  int width = 0, height = 0;
  // A sequence point is scored frame by frame while it runs: `row` is then finished, `result` is
  // its last frame's estimate, and `frames` are the rows of its frames.csv.
  bool scored = false;
  std::vector<nlohmann::json> frames;
  std::vector<KeptFrame> kept_frames;          // kept_sequence_frames(), in order
  std::map<int, double> settle_excess_by_age;  // TemporalScorer::settle_excess_by_age(), matched
  std::map<int, double> rmse_excess_by_age;    // TemporalScorer::rmse_excess_by_age(), matched
  // TemporalScorer's flicker and lag maps against the matched reference (width x height, NaN
  // where a pixel never counted); kept as the point's maps.exr (kept_sequence.h).
  std::vector<float> flicker_map, lag_map;
};

// Thread-safety: measure() on one thread may run while score() of an earlier measurement runs on
// another (the runners' background lane); the session's caches are guarded for that. Two
// concurrent measure() calls, or two concurrent score() calls, are not supported.
class EvaluationSession {
 public:
  EvaluationSession(ReferenceSpec reference, TimingSpec timing, bool disk_cache = true);
  ~EvaluationSession();

  struct SceneData {
    Scene scene;
    std::unique_ptr<EmbreeScene> embree;
    uint64_t content_hash = 0;  // scene.content_hash(), computed once at load
  };
  const SceneData& scene(const std::string& name);
  // Frame k of a view: the scene posed for it (the scene itself when no object moves), cached.
  const SceneData& frame_scene(const std::string& name, const View& view, int frame);
  // Frame k's camera (jitter included) and reference settings (seed + j for sequence views, where
  // j = reference_frame(): a frame that does not change from frame k - 1 has frame k - 1's
  // reference, traced once; issue 42).
  Camera frame_camera_of(const std::string& name, const View& view, int frame, int w, int h);
  int reference_frame(const std::string& name, const View& view, int frame);
  ReferenceSettings frame_settings(const std::string& name, const View& view, int frame,
                                   const AoDefinition& d);
  // Declares the references a request will ask for (its definition and true AO), so that the
  // first trace of a (scene, view, frame, size, weighting) traces every declared definition of
  // that weighting at once and writes each one's cache entry (issue 42). Runners declare all
  // their points before running any; measure() declares its own request in any case.
  void plan_references(const EvaluationRequest& request);
  // The definitions declared for a view at a size (view "" and size 0 of requests resolved).
  std::vector<AoDefinition> planned_definitions(const std::string& scene, const View& view, int w,
                                                int h);
  // What the session traced: passes over the rays, the reference images they gave (a pass gives
  // one per definition it shares its rays with) and the rays.
  struct ReferenceCounts {
    uint64_t traces = 0, references = 0, rays = 0;
  };
  ReferenceCounts reference_counts() {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    return counts_;
  }
  // Where one image stands for a view (gbuffer(), reference(), mosaics, the gallery), a sequence
  // view is its last frame: the state a screenshot after the sequence shows.
  static int still_frame(const View& view) { return view.frame_count() - 1; }
  // The reference of a G-buffer `g` of scene `s` seen by `camera`: from the disk cache (keyed by
  // the scene's geometry, the camera and the settings) or computed and stored there.
  // `companions`: definitions to trace with it when it is traced (their cache entries written too).
  ReferenceImage reference_image(const SceneData& s, const View& view, const Camera& camera,
                                 const GBuffer& g, const ReferenceSettings& settings,
                                 const std::vector<AoDefinition>& companions = {});
  const GBuffer& gbuffer(const std::string& scene, const View& view, int width, int height);
  const ReferenceImage& reference(const std::string& scene, const View& view, int width, int height,
                                  const AoDefinition& definition);

  // Runs and scores one request: measure() then score(). When `estimate_path` is not empty the
  // estimate EXR is written there.
  ResultRow evaluate(const EvaluationRequest& request, const std::string& estimate_path = "");
  // Runs the estimator: set-up, precompute, warm-up, then the timed frames inside the timed
  // frames' guard (if set). A missing backend gives a measurement whose row is "skipped: ...".
  Measurement measure(const EvaluationRequest& request);
  // References, metrics and (when `estimate_path` is not empty) the estimate EXR of a measurement;
  // returns the finished row. Leaves the estimate in last_estimate().
  ResultRow score(Measurement& measurement, const std::string& estimate_path = "");
  // The estimate of the last score() call (for error maps).
  const std::vector<float>& last_estimate() const { return last_estimate_; }
  // `before` is called right before every estimator's timed frames and `after` right after them
  // (also when they throw), so that the frames run alone on the machine: the runners pause and
  // resume their background lane (background_lane.h). Empty functions remove the guard.
  void set_timed_frames_guard(std::function<void()> before, std::function<void()> after) {
    before_timed_frames_ = std::move(before);
    after_timed_frames_ = std::move(after);
  }

  const ReferenceSpec& reference_spec() const { return reference_spec_; }
  // Where this session's time went (scenes, G-buffers, references, the estimators' stages,
  // scoring, estimate EXRs); runners add their own stages to theirs.
  const StageTimes& stages() const { return stages_; }

 private:
  ReferenceSpec reference_spec_;
  TimingSpec timing_;
  bool disk_cache_;
  std::function<void()> before_timed_frames_, after_timed_frames_;
  // Guards the caches below (std::map: entries never move or vanish, except FLIP's, which only
  // score() uses) against measure() and score() on two threads.
  std::recursive_mutex cache_mutex_;
  std::map<std::string, SceneData> scenes_;
  std::map<std::string, GBuffer> gbuffers_;
  std::map<std::string, ReferenceImage> references_;
  std::map<std::string, std::vector<AoDefinition>> planned_;  // "scene|view|WxH" as requested
  ReferenceCounts counts_;
  // Images traced as companions, by cache key, as their entries read back, until asked for once
  // (with a disk cache too: a cold run does not read what it has just traced).
  std::map<std::string, ReferenceImage> untaken_;
  // Traces `settings`' reference with those companions of its weighting not yet in the disk cache,
  // writes the companions' entries and returns the asked one.
  ReferenceImage trace_references(const SceneData& s, const View& view, const Camera& camera,
                                  const GBuffer& g, const ReferenceSettings& settings,
                                  const std::vector<AoDefinition>& companions);
  std::vector<float> last_estimate_;
  StageTimes stages_;
  // FLIP's reference side of each reference scored against (flip::prepare_reference).
  std::map<const ReferenceImage*, flip::ReferenceSide> flip_references_;
  const flip::ReferenceSide& flip_reference(const GBuffer& g, const ReferenceImage& reference);
  // reference() when the reference is neither in memory nor in the disk cache.
  void compute_missing_reference(const std::string& scene, const View& view, int w, int h,
                                 const AoDefinition& definition);
  void fill_identity(Measurement& m, const EvaluationRequest& request);
  void write_estimate(const Measurement& m, const std::string& path);
  // Runs and scores every frame of a sequence point in order (sequence_evaluation.cpp).
  void measure_sequence(Measurement& m, bool seed_per_frame);
};

// Header attributes of an estimate EXR.
// `derived` (Estimator::derived()) is recorded under "derived" in aoeval:params when not empty.
Attributes estimate_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                               const Camera& camera, const EstimatorInfo& e, const ParamSet& params,
                               const nlohmann::json& derived = nlohmann::json::object());
// The estimate as an image: AO, A and the estimator's extra channels.
OIIO::ImageBuf estimate_to_image(const GBuffer& g, const EstimateResult& r);

}  // namespace aoeval
