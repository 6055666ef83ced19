// Bent-normal metrics (bent_metrics.h): angles between known vectors, the percentile rule, pixels
// skipped where either vector is zero or the mask is off, and the noise removal of
// bent_angle_excess.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "harness/scoring/bent_metrics.h"

namespace aoeval {
namespace {

glm::vec3 tilted(double deg) {
  const double a = deg * 3.14159265358979323846 / 180.0;
  return {static_cast<float>(std::sin(a)), static_cast<float>(std::cos(a)), 0.0f};
}

TEST(BentMetrics, AnglesPercentileMaskAndZeros) {
  // 20 pixels: angles 1..20 degrees, one masked off, one with a zero estimate.
  std::vector<glm::vec3> ref(22, glm::vec3(0, 1, 0)), est(22);
  for (int k = 0; k < 20; ++k) est[k] = tilted(k + 1) * 3.0f;  // length does not matter
  est[20] = glm::vec3(0.0f);                                   // no bent normal: skipped
  est[21] = tilted(90);
  std::vector<uint8_t> mask(22, 1);
  mask[21] = 0;  // masked off
  const auto m = compare_bent(22, 1, ref, est, mask, {});
  ASSERT_TRUE(m);
  EXPECT_EQ(m->pixels, 20u);
  EXPECT_NEAR(m->angle_mean, 10.5, 1e-3);
  EXPECT_NEAR(m->angle_p95, 19.0, 1e-3);  // ceil(0.95 * 20) = 19th smallest
  EXPECT_EQ(m->ref_stderr, 0.0);
  double sq = 0.0;
  for (int k = 1; k <= 20; ++k) sq += k * k;
  EXPECT_NEAR(m->angle_excess, std::sqrt(sq / 20.0), 1e-3);
  nlohmann::json j = nlohmann::json::object();
  add_bent_json(*m, j, "true_");
  for (const auto& k : bent_metric_keys()) EXPECT_TRUE(j.contains("true_" + k)) << k;
}

TEST(BentMetrics, ExcessRemovesTheReferenceNoise) {
  // Every angle 5 degrees, the reference's stderr 3 degrees: excess sqrt(25 - 9) = 4.
  std::vector<glm::vec3> ref(10, glm::vec3(0, 1, 0)), est(10, tilted(5));
  const auto m = compare_bent(10, 1, ref, est, {}, std::vector<float>(10, 3.0f));
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->ref_stderr, 3.0, 1e-6);
  EXPECT_NEAR(m->angle_excess, 4.0, 1e-3);
  // Noise larger than the angles: clamped at 0, as rmse_excess is.
  EXPECT_EQ(compare_bent(10, 1, ref, est, {}, std::vector<float>(10, 9.0f))->angle_excess, 0.0);
}

TEST(BentMetrics, NothingComparableAndBadInput) {
  std::vector<glm::vec3> ref(4, glm::vec3(0.0f)), est(4, glm::vec3(0, 1, 0));
  EXPECT_FALSE(compare_bent(2, 2, ref, est, {}, {}));  // the reference has no bent normal
  EXPECT_THROW(compare_bent(3, 2, ref, est, {}, {}), InputError);
  est[1].x = std::nanf("");
  ref.assign(4, glm::vec3(0, 1, 0));
  EXPECT_THROW(compare_bent(2, 2, ref, est, {}, {}), InputError);
  EXPECT_FALSE(bent_of_channels(nullptr, nullptr, nullptr));
}

}  // namespace
}  // namespace aoeval
