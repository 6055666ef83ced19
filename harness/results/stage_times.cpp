#include "harness/results/stage_times.h"

#include <algorithm>
#include <cstdio>

namespace aoeval {

void StageTimes::add(const std::string& stage, double ms) {
  for (auto& [name, total] : stages_)
    if (name == stage) {
      total += ms;
      return;
    }
  stages_.emplace_back(stage, ms);
}

void StageTimes::add_all(const StageTimes& other) {
  for (const auto& [name, total] : other.stages_) add(name, total);
}

double StageTimes::ms(const std::string& stage) const {
  for (const auto& [name, total] : stages_)
    if (name == stage) return total;
  return 0.0;
}

double StageTimes::total_ms() const {
  double sum = 0.0;
  for (const auto& [name, total] : stages_) sum += total;
  return sum;
}

double StageTimes::estimator_ms() const {
  return ms(kEstimatorPrecompute) + ms(kEstimatorWarmup) + ms(kEstimatorFrames);
}

nlohmann::json StageTimes::to_json() const {
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
  for (const auto& [name, total] : stages_) row(name, total);
  row("other (untimed)", std::max(0.0, wall_ms - total_ms()));
  std::snprintf(line, sizeof line, "  %-28s %10.0f ms  %5.1f %%  (estimator share of wall time)\n",
                "wall", wall_ms, 100.0 * estimator_ms() / wall);
  out += line;
  return out;
}

}  // namespace aoeval
