// Where a run's wall time goes (issue 16): named stages with their summed milliseconds, in the
// order they were first used. The evaluation session times its stages (scene, G-buffer, reference,
// the estimator's set-up, precompute, warm-up and timed frames, scoring, estimate EXR) and the
// runners add theirs (results files, SQLite, mosaics, report); the breakdown is printed at the end
// of `aoeval run` and `aoeval sweep` and stored in the run's context ("stages_ms").
#pragma once

#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace aoeval {

// Thread-safe: a sweep's background lane (harness/evaluation/background_lane.h) adds the stages it
// runs while the estimators precompute and warm up; they are recorded under the stage's name
// followed by kOverlapped, are shown apart and are not part of total_ms() (they hide behind the
// foreground's time instead of adding to the wall time).
class StageTimes {
 public:
  StageTimes() = default;
  StageTimes(const StageTimes& other);
  StageTimes& operator=(const StageTimes& other);

  void add(const std::string& stage, double ms);
  void add_all(const StageTimes& other);      // every stage of `other` added to this
  double ms(const std::string& stage) const;  // 0 for a stage never timed
  double total_ms() const;  // the foreground stages' sum (overlapped ones excluded)
  // The estimator's own share: precompute, warm-up and timed frames (what a sweep exists to
  // measure); its set-up (creating pipelines, compiling shaders) is counted apart.
  double estimator_ms() const;
  nlohmann::json to_json() const;  // {"stage": ms, ...}
  // (stage, ms) in first-use order.
  std::vector<std::pair<std::string, double>> entries() const;
  // One line per foreground stage, in first-use order, with its share of `wall_ms`, the rest as
  // "other (untimed)", the overlapped stages apart, and the estimator share as the last line.
  std::string table(double wall_ms) const;

  // Adds the time from construction to destruction to `stage`.
  class Scope {
   public:
    Scope(StageTimes& times, std::string stage)
        : times_(times), stage_(std::move(stage)), t0_(std::chrono::steady_clock::now()) {}
    ~Scope() {
      times_.add(stage_,
                 std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_)
                     .count());
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimes& times_;
    std::string stage_;
    std::chrono::steady_clock::time_point t0_;
  };
  Scope time(std::string stage) { return Scope(*this, std::move(stage)); }

  // The stage names the session uses, so runners and the breakdown agree on them.
  static constexpr const char* kEstimatorPrecompute = "estimator precompute";
  static constexpr const char* kEstimatorWarmup = "estimator warm-up";
  static constexpr const char* kEstimatorFrames = "estimator timed frames";
  // Time the runner's thread waited for its background lane: for the job in progress to finish
  // before timed frames (or for room in a full queue), and for the jobs left after the last point.
  static constexpr const char* kWaitingForBackground = "waiting for background work";
  static constexpr const char* kBackgroundLeftAtEnd = "background work left at the end";
  // The suffix of a stage run on a background thread, and the marking of such a thread.
  static constexpr const char* kOverlapped = " (overlapped)";
  static void mark_this_thread_overlapped();

 private:
  void add_locked(const std::string& stage, double ms);
  mutable std::mutex mutex_;
  std::vector<std::pair<std::string, double>> stages_;
};

}  // namespace aoeval
