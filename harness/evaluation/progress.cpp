#include "harness/evaluation/progress.h"

#include <unistd.h>

#include <algorithm>
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

void Progress::note(std::string text) {
  std::lock_guard<std::mutex> lock(mutex_);
  note_ = std::move(text);
}

std::string Progress::line(size_t done, size_t total, double elapsed_s, const std::string& note,
                           const std::string& what) {
  const int width = 30;
  const int filled = total ? static_cast<int>(width * std::min(done, total) / total) : width;
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%s] %zu/%zu %.0fs", bar.c_str(), done, total, elapsed_s);
  std::string out = buf;
  if (done > 0 && done < total) {
    std::snprintf(buf, sizeof buf, ", ~%.0fs left",
                  elapsed_s / static_cast<double>(done) * static_cast<double>(total - done));
    out += buf;
  }
  if (!note.empty()) out += ", " + note;
  if (!what.empty()) out += "  " + what;
  return out;
}

void Progress::draw(const std::string& what) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "\r\033[K%s %s", task_.c_str(),
               line(done_, total_, elapsed, note_, what).c_str());
  std::fflush(stderr);
}

}  // namespace aoeval
