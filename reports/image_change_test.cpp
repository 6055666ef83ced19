// The change of an estimate against its baseline (image_change.h): a uniform darkening is found on
// every pixel; two draws of the same noisy estimator with other seeds are not a change, whether the
// noise is known (AO_stderr) or estimated from the difference image (high-pass rule).
#include "reports/image_change.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace aoeval {
namespace {

constexpr int kW = 96, kH = 64;

// A smooth AO image with a background corner; `noise` per-pixel Gaussian sd, `stderr_ao` stored.
AoPlanes image(double scale, double noise, uint64_t seed, bool with_stderr) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  AoPlanes p;
  p.w = kW;
  p.h = kH;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double truth = 0.55 + 0.3 * std::sin(0.07 * x) * std::cos(0.05 * y);
      p.ao.push_back(static_cast<float>(scale * truth + noise * gauss(rng)));
      p.covered.push_back(!(x < 8 && y < 8));
      if (with_stderr) p.stderr_ao.push_back(static_cast<float>(noise));
    }
  return p;
}

TEST(ImageChange, ADarkeningIsFoundOnEveryPixelAndAnIdenticalRerunIsNot) {
  const AoPlanes base = image(1.0, 0.0, 1, false);
  const ImageChange same = compare_estimates(base, base, false);
  EXPECT_EQ(same.mean_shift, 0.0);
  EXPECT_EQ(same.changed_pixels, 0.0);
  EXPECT_EQ(same.noise_rule, "deterministic");
  EXPECT_EQ(same.pixels, static_cast<size_t>(kW * kH - 64));
  EXPECT_FALSE(std::abs(same.mean_shift) > change_threshold(same, 0.005));

  const ImageChange darker = compare_estimates(base, image(0.9, 0.0, 1, false), false);
  double mean = 0.0;
  for (size_t k = 0; k < base.ao.size(); ++k) mean += base.covered[k] ? base.ao[k] : 0.0;
  mean /= static_cast<double>(darker.pixels);
  EXPECT_NEAR(darker.mean_shift, -0.1 * mean, 1e-6);
  EXPECT_EQ(darker.changed_pixels, 1.0);
  EXPECT_GT(std::abs(darker.mean_shift), change_threshold(darker, 0.005));
  EXPECT_EQ(change_phrase(darker).rfind("darker by 0.05", 0), 0u) << change_phrase(darker);
  EXPECT_NE(change_phrase(darker).find("mean AO on 100 % of pixels"), std::string::npos);
  EXPECT_THROW(compare_estimates(base, AoPlanes{}, false), std::invalid_argument);
}

TEST(ImageChange, AnotherSeedIsNoChangeUnderEitherNoiseRule) {
  for (bool with_stderr : {true, false}) {
    // Noise of 0.1 per pixel (a few rays): the mean of the difference has sd 0.1 sqrt(2 / 6080)
    // = 0.0018, so change_mean_shift 0.005 alone would flag about one reseed in 200.
    const AoPlanes a = image(1.0, 0.1, 11, with_stderr), b = image(1.0, 0.1, 12, with_stderr);
    const ImageChange c = compare_estimates(a, b, true);
    EXPECT_EQ(c.noise_rule, with_stderr ? "stderr" : "high-pass");
    // |new - old| has sd 0.1 sqrt(2): the per-pixel threshold is about four of those.
    EXPECT_NEAR(c.pixel_threshold, 4.0 * 0.1 * std::sqrt(2.0), with_stderr ? 1e-3 : 0.06);
    EXPECT_LT(c.changed_pixels, 0.002) << with_stderr;
    EXPECT_LT(std::abs(c.mean_shift), change_threshold(c, 0.005)) << with_stderr;
    // The same seed: the deterministic rule, and identical images.
    EXPECT_EQ(compare_estimates(a, a, false).changed_pixels, 0.0);
    // A real darkening through the same noise is still a change.
    const ImageChange dark = compare_estimates(a, image(0.9, 0.1, 12, with_stderr), true);
    EXPECT_GT(std::abs(dark.mean_shift), change_threshold(dark, 0.005)) << with_stderr;
    EXPECT_LT(dark.mean_shift, -0.04);
  }
}

}  // namespace
}  // namespace aoeval
