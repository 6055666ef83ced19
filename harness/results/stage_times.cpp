#include "harness/results/stage_times.h"

#include <algorithm>
#include <cstdio>

namespace aoeval {

namespace {
thread_local bool t_overlapped = false;

bool is_overlapped(const std::string& stage) {
  const std::string suffix = StageTimes::kOverlapped;
  return stage.size() >= suffix.size() &&
         stage.compare(stage.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

void StageTimes::mark_this_thread_overlapped() {
  t_overlapped = true;
}

StageTimes::StageTimes(const StageTimes& other) {
  std::lock_guard<std::mutex> lock(other.mutex_);
  stages_ = other.stages_;
}

StageTimes& StageTimes::operator=(const StageTimes& other) {
  if (this == &other) return *this;
  const auto copy = other.entries();
  std::lock_guard<std::mutex> lock(mutex_);
  stages_ = copy;
  return *this;
}

std::vector<std::pair<std::string, double>> StageTimes::entries() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stages_;
}

void StageTimes::add(const std::string& stage, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  add_locked(t_overlapped && !is_overlapped(stage) ? stage + kOverlapped : stage, ms);
}

void StageTimes::add_locked(const std::string& stage, double ms) {
  for (auto& [name, total] : stages_)
    if (name == stage) {
      total += ms;
      return;
    }
  stages_.emplace_back(stage, ms);
}

void StageTimes::add_all(const StageTimes& other) {
  const auto theirs = other.entries();  // names already carry their overlapped mark
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [name, total] : theirs) add_locked(name, total);
}

double StageTimes::ms(const std::string& stage) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [name, total] : stages_)
    if (name == stage) return total;
  return 0.0;
}

double StageTimes::total_ms() const {
  std::lock_guard<std::mutex> lock(mutex_);
  double sum = 0.0;
  for (const auto& [name, total] : stages_)
    if (!is_overlapped(name)) sum += total;
  return sum;
}

double StageTimes::estimator_ms() const {
  return ms(kEstimatorPrecompute) + ms(kEstimatorWarmup) + ms(kEstimatorFrames);
}

nlohmann::json StageTimes::to_json() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, total] : stages_) j[name] = total;
  return j;
}

std::string StageTimes::table(double wall_ms) const {
  std::string out;
  char line[160];
  const double wall = std::max(wall_ms, 1e-9);
  auto row = [&](const std::string& name, double ms) {
    std::snprintf(line, sizeof line, "  %-28s %10.0f ms  %5.1f %%\n", name.c_str(), ms,
                  100.0 * ms / wall);
    out += line;
  };
  const auto stages = entries();
  bool any_overlapped = false;
  for (const auto& [name, total] : stages)
    if (is_overlapped(name))
      any_overlapped = true;
    else
      row(name, total);
  row("other (untimed)", std::max(0.0, wall_ms - total_ms()));
  if (any_overlapped) {
    out +=
        "  in the background while estimators precomputed and warmed up (not in the wall time):\n";
    for (const auto& [name, total] : stages)
      if (is_overlapped(name))
        row(name.substr(0, name.size() - std::string(kOverlapped).size()), total);
  }
  std::snprintf(line, sizeof line, "  %-28s %10.0f ms  %5.1f %%  (estimator share of wall time)\n",
                "wall", wall_ms, 100.0 * estimator_ms() / wall);
  out += line;
  return out;
}

}  // namespace aoeval
