// The Pareto rule of error against time (pareto.h).
#include "harness/results/pareto.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/summary.h"

namespace aoeval {

std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error,
                               const std::vector<double>& cost_noise) {
  if (cost.size() != error.size() || (!cost_noise.empty() && cost_noise.size() != cost.size()))
    throw std::invalid_argument("pareto_front: cost, error and cost_noise differ in length");
  const size_t n = cost.size();
  auto noise = [&](size_t k) { return cost_noise.empty() ? 0.0 : std::max(0.0, cost_noise[k]); };
  auto valid = [&](size_t k) { return !std::isnan(cost[k]) && !std::isnan(error[k]); };
  std::vector<bool> front(n, false);
  for (size_t i = 0; i < n; ++i) {
    if (!valid(i)) continue;
    bool dominated = false;
    for (size_t j = 0; j < n && !dominated; ++j) {
      if (j == i || !valid(j)) continue;
      const double t = std::max(noise(i), noise(j));
      dominated = error[j] <= error[i] && cost[j] <= cost[i] + t &&
                  (error[j] < error[i] || cost[j] < cost[i] - t);
    }
    front[i] = !dominated;
  }
  return front;
}

double pareto_time_noise(const ResultRow& row) {
  return interquartile_range(row.time_ms_samples);
}

}  // namespace aoeval
