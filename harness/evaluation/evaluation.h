// One evaluation = an estimator with its parameters on one scene view at one resolution: run it
// (precompute, warm-up, timed repetitions), score it against the reference of its own AO definition
// ("matched") and against true AO, and return a results row. A still view is a one-frame
// sequence: run_frames() runs every frame of a point alike (frames.cpp), score_frame() scores each.
// The session is thin: what runs share is in its SceneCache (scenes, posed frames, G-buffers) and
// its ReferenceStore (references in memory and on disk, FLIP's reference sides).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "estimators/estimator.h"
#include "harness/evaluation/reference_store.h"
#include "harness/evaluation/scene_cache.h"
#include "harness/results/result_row.h"
#include "harness/results/stage_times.h"

namespace aoeval {

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

// What a sequence's scoring carries from frame to frame (frames.cpp).
struct SequenceScoring;

// What an evaluation measured before it is scored: the row so far (identity, timings, status),
// the last frame's estimate and what scoring needs to find its references. measure() scores a
// sequence's frames as they run except the last, at once or on set_background()'s lane (a frame's
// G-buffer and references are dropped once scored); score() scores the last frame, a still's only
// one, and finishes the row. `frames` holds the scored frames' rows: after score() all of them.
struct Measurement {
  ResultRow row;
  EstimateResult result;
  const EstimatorInfo* estimator = nullptr;
  ParamSet params;
  nlohmann::json derived;
  std::string scene;
  const View* view = nullptr;
  int width = 0, height = 0;
  // A sequence point's, complete after score(): the rows of its frames.csv, its kept frames, and
  // TemporalScorer's matched by-age excesses and flicker and lag maps (width x height, NaN where a
  // pixel never counted; kept as the point's maps.exr, kept_sequence.h).
  std::vector<nlohmann::json> frames;
  std::vector<KeptFrame> kept_frames;  // kept_sequence_frames(), in order
  std::map<int, double> settle_excess_by_age;
  std::map<int, double> rmse_excess_by_age;
  std::vector<float> flicker_map, lag_map;
  std::shared_ptr<SequenceScoring> sequence;  // a sequence's, until score(); null for a still
};

// Thread-safety: measure() on one thread may run while score() of an earlier measurement runs on
// another (the runners' background lane); the session's caches are guarded for that. Two
// concurrent measure() calls, or two concurrent score() calls, are not supported.
class EvaluationSession {
 public:
  EvaluationSession(ReferenceSpec reference, TimingSpec timing, bool disk_cache = true);
  ~EvaluationSession();

  SceneCache& scenes() { return scenes_; }
  ReferenceStore& references() { return references_; }

  using SceneData = aoeval::SceneData;
  const SceneData& scene(const std::string& name) { return scenes_.scene(name); }
  const SceneData& frame_scene(const std::string& name, const View& view, int frame) {
    return scenes_.frame_scene(name, view, frame);
  }
  int reference_frame(const std::string& name, const View& view, int frame) {
    return scenes_.reference_frame(name, view, frame);
  }
  ReferenceSettings frame_settings(const std::string& name, const View& view, int frame,
                                   const AoDefinition& d) {
    return references_.frame_settings(name, view, frame, d);
  }
  static int still_frame(const View& view) { return SceneCache::still_frame(view); }
  const GBuffer& gbuffer(const std::string& scene, const View& view, int width, int height) {
    return scenes_.gbuffer(scene, view, width, height);
  }
  const ReferenceImage& reference(const std::string& scene, const View& view, int width, int height,
                                  const AoDefinition& definition) {
    return references_.reference(scene, view, width, height, definition);
  }
  // Declares the references a request will ask for (its definition and true AO), so that the
  // first trace of a (scene, view, frame, size, weighting) traces every declared definition of
  // that weighting at once and writes each one's cache entry (issue 42). Runners declare all
  // their points before running any; measure() declares its own request in any case.
  void plan_references(const EvaluationRequest& request);
  using ReferenceCounts = ReferenceStore::Counts;
  ReferenceCounts reference_counts() { return references_.counts(); }

  // Runs and scores one request: measure() then score(). When `estimate_path` is not empty the
  // estimate EXR is written there.
  ResultRow evaluate(const EvaluationRequest& request, const std::string& estimate_path = "");
  // Runs the estimator over the view's frames (one for a still): set-up, precompute, warm-up,
  // then each frame's timed runs inside the timed frames' guard (if set); a sequence's frames but
  // the last are scored as they run (posted to set_background()'s lane when one is set). Warm-up
  // runs for Vulkan and process estimators only (frames.cpp). A missing backend gives a
  // measurement whose row is
  // "skipped: ...".
  Measurement measure(const EvaluationRequest& request);
  // Scores the measurement's last frame (a still's only one), finishes its row and (when
  // `estimate_path` is not empty) writes the estimate EXR; returns the finished row. Leaves the
  // estimate in last_estimate().
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

  // Where work that may wait goes: `post` runs a job later, jobs in the order posted (the
  // runners' background lane, whose pause guards the timed frames). A sequence's frames but the
  // last are scored there, and traced companions' cache entries written there; score() must then
  // run after the measurement's jobs (on the same lane). Empty: done at once.
  void set_background(std::function<void(std::function<void()>)> post) {
    background_ = post;
    references_.set_writer(std::move(post));
  }

  // How score() writes a still's estimate EXR (`estimate_path`): write_exr, every value as the
  // estimator gave it, unless set. A suite run sets the compact writer (kept_references.h
  // write_compact_estimate), so the file is written once, compact.
  using EstimateWriter = std::function<void(const std::string& path, const OIIO::ImageBuf& image,
                                            const Attributes& attributes)>;
  void set_estimate_writer(EstimateWriter writer) { estimate_writer_ = std::move(writer); }

  const ReferenceSpec& reference_spec() const { return references_.spec(); }
  // Where this session's time went (scenes, G-buffers, references, the estimators' stages,
  // scoring, estimate EXRs); runners add their own stages to theirs.
  const StageTimes& stages() const { return stages_; }

  // One frame to score: its G-buffer, estimate and references (frames.cpp).
  struct FrameToScore;

 private:
  StageTimes stages_;  // before the caches, which time into it
  SceneCache scenes_;
  ReferenceStore references_;
  TimingSpec timing_;
  std::function<void()> before_timed_frames_, after_timed_frames_;
  std::function<void(std::function<void()>)> background_;
  EstimateWriter estimate_writer_;
  std::vector<float> last_estimate_;
  void fill_identity(Measurement& m, const EvaluationRequest& request);
  void write_estimate(const Measurement& m, const std::string& path);
  // Runs every frame of the measurement's view in order (frames.cpp).
  void run_frames(Measurement& m, bool seed_per_frame);
  // The timed runs of one frame inside the guard, until `enough` holds for the frame's times
  // (appended to `times`); `result` is the last run's estimate (frames.cpp).
  void run_timed(Estimator& estimator, const EstimateContext& context,
                 const std::function<bool(const std::vector<double>&)>& enough,
                 std::vector<double>& times, std::map<std::string, std::vector<double>>& passes,
                 EstimateResult& result);
  // Scores one frame (frames.cpp): the row's metrics when it is the last, a sequence's frames.csv
  // row and temporal scorers (`sequence`, null for a still); `row` is needed for the last only.
  void score_frame(SequenceScoring* sequence, ResultRow* row, const FrameToScore& frame);
};

// Header attributes of an estimate EXR.
// `derived` (Estimator::derived()) is recorded under "derived" in aoeval:params when not empty.
Attributes estimate_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                               const Camera& camera, const EstimatorInfo& e, const ParamSet& params,
                               const nlohmann::json& derived = nlohmann::json::object());
// The estimate as an image: AO, A and the estimator's extra channels.
OIIO::ImageBuf estimate_to_image(const GBuffer& g, const EstimateResult& r);

}  // namespace aoeval
