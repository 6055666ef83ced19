#include "harness/scoring/bent_metrics.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <numbers>

#include "base/errors.h"
#include "harness/results/metric_table.h"

namespace aoeval {

namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string pixel_name(size_t k, int width) {
  return "(" + std::to_string(k % static_cast<size_t>(width)) + ", " +
         std::to_string(k / static_cast<size_t>(width)) + ")";
}

}  // namespace

std::optional<BentMetrics> compare_bent(int width, int height, const std::vector<glm::vec3>& ref,
                                        const std::vector<glm::vec3>& est,
                                        const std::vector<uint8_t>& mask,
                                        const std::vector<float>& ref_stderr) {
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (ref.size() != n || est.size() != n || (!mask.empty() && mask.size() != n) ||
      (!ref_stderr.empty() && ref_stderr.size() != n))
    throw InputError("bent normals: the reference, estimate, mask and stderr sizes differ from " +
                     std::to_string(width) + "x" + std::to_string(height));
  std::vector<double> angles;
  double sum = 0.0, sum_sq = 0.0, var = 0.0;
  for (size_t k = 0; k < n; ++k) {
    if (!mask.empty() && !mask[k]) continue;
    if (!finite(ref[k]))
      throw InputError("reference bent normal is not finite at pixel " + pixel_name(k, width));
    if (!finite(est[k]))
      throw InputError("estimate bent normal is not finite at pixel " + pixel_name(k, width));
    const glm::dvec3 a(ref[k]), b(est[k]);
    const double la = glm::length(a), lb = glm::length(b);
    if (!(la > 0.0) || !(lb > 0.0)) continue;
    const double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
    const double angle = std::acos(c) * 180.0 / std::numbers::pi;
    angles.push_back(angle);
    sum += angle;
    sum_sq += angle * angle;
    if (!ref_stderr.empty()) var += static_cast<double>(ref_stderr[k]) * ref_stderr[k];
  }
  if (angles.empty()) return std::nullopt;
  BentMetrics m{};
  const auto count = static_cast<double>(angles.size());
  m.pixels = angles.size();
  m.angle_mean = sum / count;
  const size_t rank = static_cast<size_t>(std::ceil(0.95 * count));
  std::nth_element(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(rank - 1),
                   angles.end());
  m.angle_p95 = angles[rank - 1];
  m.ref_stderr = std::sqrt(var / count);
  m.angle_excess = std::sqrt(std::max(0.0, sum_sq / count - var / count));
  return m;
}

void add_bent_json(const BentMetrics& m, nlohmann::json& out, const std::string& prefix) {
  out[prefix + "bent_pixels"] = m.pixels;
  out[prefix + "bent_angle_mean"] = m.angle_mean;
  out[prefix + "bent_angle_p95"] = m.angle_p95;
  out[prefix + "bent_ref_stderr"] = m.ref_stderr;
  out[prefix + "bent_angle_excess"] = m.angle_excess;
}

std::vector<std::string> bent_metric_keys() {
  return metric_keys_of(MetricFamily::bent);
}

std::optional<std::vector<glm::vec3>> bent_of_channels(const std::vector<float>* x,
                                                       const std::vector<float>* y,
                                                       const std::vector<float>* z) {
  if (!x || !y || !z || x->size() != y->size() || x->size() != z->size()) return std::nullopt;
  std::vector<glm::vec3> v(x->size());
  for (size_t k = 0; k < v.size(); ++k) v[k] = glm::vec3((*x)[k], (*y)[k], (*z)[k]);
  return v;
}

}  // namespace aoeval
