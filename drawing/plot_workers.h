// Pre-started plot.py processes (`plot.py --serve`), so that a suite's report does not wait for
// Python to start and import matplotlib (about 0.6 s of CPU per process, a third of the quick
// suite's report; issue 16). A run starts them early; they import while the estimators precompute
// and warm up, are stopped (SIGSTOP) while timed frames run so the frames stay alone on the
// machine, and draw the report's charts at the end. render_plots() uses an idle worker when one
// was started and starts a process of its own otherwise, so nothing depends on them.
#pragma once

#include <sys/types.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace aoeval {

class PlotWorkers {
 public:
  // The process-wide pool (empty until start()).
  static PlotWorkers& instance();
  ~PlotWorkers();

  // Starts workers until `count` are alive (never more). Quietly starts none when the interpreter
  // cannot be run: render_plots() then reports the reason, as before.
  void start(int count);
  // SIGSTOP / SIGCONT every worker: around timed frames (EvaluationSession's timed-frames guard).
  void freeze();
  void thaw();
  // Ends the idle workers (call it when no plot is being drawn); the pool can start again.
  void stop();

  // Process ids of the live workers (for tests and diagnostics).
  std::vector<pid_t> pids();

  struct Worker;
  // An idle worker, or nullptr when none is alive and idle. Give it back with release().
  Worker* acquire();
  void release(Worker* worker);
  // Draws one plot; false (the worker is then dead and will not be handed out again) when the
  // process is gone or answers nothing, so the caller falls back to a process of its own. An
  // answer "error: ..." is a plot error: it throws std::runtime_error with that message.
  static bool draw(Worker& worker, const std::string& spec_path, const std::string& out_path);

 private:
  PlotWorkers() = default;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Worker>> workers_;
  bool frozen_ = false;
};

}  // namespace aoeval
