#include "harness/evaluation/progress.h"

#include <unistd.h>

#include <cstdio>

namespace aoeval {

Progress::Progress(std::string task, size_t total)
    : task_(std::move(task)),
      total_(total),
      enabled_(isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {
  if (enabled_) draw("");
}

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\n");
}

void Progress::step(const std::string& what) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  if (enabled_) draw(what);
}

void Progress::draw(const std::string& what) {
  const int width = 30;
  const int filled = total_ ? static_cast<int>(width * done_ / total_) : width;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r\033[K%s [%s] %zu/%zu %.0fs %s", task_.c_str(), bar.c_str(), done_,
               total_, elapsed, what.c_str());
  std::fflush(stderr);
}

}  // namespace aoeval
