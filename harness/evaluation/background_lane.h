// A sweep's post-estimate work (scoring, the estimate EXR, mosaics, results rows) run on one
// background thread while the next points' estimators load, compile, precompute and warm up
// (issue 16). The estimators' timed frames must still run alone on the machine: the session calls
// pause() right before them and resume() right after (EvaluationSession::set_timed_frames_guard).
// pause() returns once no job is running, and no job starts until resume(), so nothing of the
// lane runs while frames are timed; jobs queued meanwhile wait for the next untimed stretch. Jobs
// run one at a time in the order posted, so rows reach the results in the order the points ran,
// as without the lane.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace aoeval {

class BackgroundLane {
 public:
  // At most `max_queued` jobs wait; post() blocks beyond that (each holds a frame's estimate).
  explicit BackgroundLane(size_t max_queued = 32);
  // Resumes and waits for the posted jobs; an error they raised and nobody drained is dropped (a
  // destructor cannot throw: call drain() first to see it).
  ~BackgroundLane();
  BackgroundLane(const BackgroundLane&) = delete;
  BackgroundLane& operator=(const BackgroundLane&) = delete;

  // Queues `job`. Rethrows the error of an earlier job instead; the jobs queued behind a failed
  // one are dropped, since a failed point ends the run. Stages timed by a job are recorded as
  // overlapped (StageTimes::kOverlapped). Must not be called while paused with a full queue.
  void post(std::function<void()> job);
  // Returns when every posted job has run (resuming a paused lane); rethrows the first error.
  void drain();
  // Returns once no job is running or every running job waits at a checkpoint; nothing runs
  // until resume().
  void pause();
  void resume();
  // Called by a job between its steps (and a no-op off a lane's thread): when the lane is paused,
  // waits here until it resumes. Keeps pause() from waiting for a whole job.
  static void checkpoint();
  // True on a lane's own thread (where posting to it could wait for itself).
  static bool on_lane_thread();

 private:
  void work();
  void wait_while_paused(std::unique_lock<std::mutex>& lock);
  void rethrow_locked(std::unique_lock<std::mutex>& lock);

  const size_t max_queued_;
  std::mutex mutex_;
  std::condition_variable wake_, changed_;
  std::deque<std::function<void()>> jobs_;
  bool busy_ = false, paused_ = false, stopping_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace aoeval
