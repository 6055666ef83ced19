// The kept files' precision (kept_references.h): every value rounded to the nearest float16, still
// float32, within 2^-11 of it relative (4.9e-4 absolute in [0, 1]), idempotent, and a value
// beyond float16's range kept as it is; and the sweep spec's adaptive timing keys.
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "harness/sweep/kept_references.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {
namespace {

TEST(KeptReferences, HalfPrecisionIsWithinFloat16sStepAndIdempotent) {
  OIIO::ImageSpec spec(64, 4, 2, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf image(spec);
  double worst = 0.0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 64; ++x) {
      const float v[2] = {static_cast<float>(std::fmod(0.0123457 * (1 + x + 64 * y), 1.0)),
                          y == 3 ? 1.0e6f : 1e-3f * static_cast<float>(x)};
      image.setpixel(x, y, v);
    }
  const OIIO::ImageBuf rounded = at_half_precision(image);
  ASSERT_EQ(rounded.spec().format, OIIO::TypeDesc::FLOAT);
  bool changed = false;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 2; ++c) {
        const float before = image.getchannel(x, y, 0, c), after = rounded.getchannel(x, y, 0, c);
        if (before == 1.0e6f) {
          EXPECT_EQ(after, before);  // beyond float16's range: kept
          continue;
        }
        changed = changed || after != before;
        EXPECT_LE(std::fabs(after - before), std::ldexp(std::fabs(before), -11) + 3e-8f);
        if (before <= 1.0f) worst = std::max(worst, std::fabs(double(after) - before));
      }
  EXPECT_TRUE(changed);
  EXPECT_LE(worst, 4.9e-4);
  const OIIO::ImageBuf again = at_half_precision(rounded);
  for (int x = 0; x < 64; ++x)
    EXPECT_EQ(again.getchannel(x, 1, 0, 0), rounded.getchannel(x, 1, 0, 0));
}

TEST(KeptReferences, AdaptiveTimingKeysParse) {
  nlohmann::json j = {{"name", "t"},
                      {"scenes", {"bunny"}},
                      {"runs", {{{"estimator", "constant"}}}},
                      {"timing", {{"repetitions", 3}, {"max_repetitions", 15}}}};
  const SweepSpec s = parse_sweep_spec(j, "spec.json");
  EXPECT_EQ(s.timing.repetitions, 3);
  EXPECT_EQ(s.timing.max_repetitions, 15);
  EXPECT_DOUBLE_EQ(s.timing.median_ci, 0.05);
  j["timing"] = {{"repetitions", 5}};
  EXPECT_EQ(parse_sweep_spec(j, "spec.json").timing.max_repetitions, 5);  // fixed, as before
  j["timing"] = {{"repetitions", 5}, {"max_repetitions", 4}};
  EXPECT_THROW(parse_sweep_spec(j, "spec.json"), InputError);  // the maximum below the least
}

}  // namespace
}  // namespace aoeval
