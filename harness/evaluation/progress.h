// Progress on stderr for long work (CONTRACT §2): a one-line bar when stderr is a terminal, nothing
// at all otherwise, so logs and pipes stay free of control characters.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

namespace aoeval {

class Progress {
 public:
  Progress(std::string task, size_t total);
  ~Progress();
  // Marks one more unit done; `what` names the unit just finished (shown on the bar).
  void step(const std::string& what = "");
  // A standing note shown on the bar from the next draw on (e.g. "references 12 traced").
  void note(std::string text);
  // The bar's text after `task`: "[####....] done/total elapsed, ~left, note, what"; the time left
  // extrapolates the mean time per unit so far (nothing before the first unit is done).
  static std::string line(size_t done, size_t total, double elapsed_s, const std::string& note,
                          const std::string& what);

 private:
  void draw(const std::string& what);
  std::string task_;
  size_t total_;
  size_t done_ = 0;
  std::string note_;
  bool enabled_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace aoeval
