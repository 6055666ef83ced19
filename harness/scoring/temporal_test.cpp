// The sequence scores (temporal.h) on synthetic frames whose answer is known exactly.
#include "harness/scoring/temporal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace aoeval {
namespace {

struct Frame {
  std::vector<float> est, ref, stderr_, motion, disoccluded;
  std::vector<uint8_t> compared;
  TemporalFrame view(int w, int h) {
    TemporalFrame f;
    f.width = w;
    f.height = h;
    f.est = est.data();
    f.ref = ref.data();
    f.ref_stderr = stderr_.data();
    f.compared = compared.data();
    f.motion = motion.empty() ? nullptr : motion.data();
    f.disoccluded = disoccluded.empty() ? nullptr : disoccluded.data();
    return f;
  }
};

Frame frame_of(int n, float est, float ref, float se) {
  return Frame{
      std::vector<float>(n, est), std::vector<float>(n, ref), std::vector<float>(n, se), {}, {},
      std::vector<uint8_t>(n, 1)};
}

TEST(TemporalScores, ConstantErrorHasNoFlickerAndConvergesAtOnce) {
  TemporalScorer s;
  for (int k = 0; k < 6; ++k) {
    Frame f = frame_of(16, 0.5f, 0.8f, 0.0f);
    s.add_frame(f.view(4, 4));
  }
  const auto j = s.scores();
  EXPECT_EQ(j["seq_frames"], 6);
  EXPECT_NEAR(j["seq_rmse_excess"].get<double>(), 0.3, 1e-6);
  EXPECT_NEAR(j["steady_rmse_excess"].get<double>(), 0.3, 1e-6);
  EXPECT_NEAR(j["temporal_rmse"].get<double>(), 0.0, 1e-7);
  EXPECT_EQ(j["converge_frames"], 0);
  EXPECT_TRUE(j["settle_frames"].is_null());
  EXPECT_TRUE(j["disocclusion_rmse_excess"].is_null());
}

TEST(TemporalScores, FlickerIsTheFrameToFrameDifferenceLessTheReferenceNoise) {
  // est alternates 0.4 / 0.6 around a fixed ref: d = +-0.2 every frame after the first; the
  // reference's stderr 0.01 per frame gives mean noise 2 * 0.01^2.
  TemporalScorer s;
  for (int k = 0; k < 5; ++k) {
    Frame f = frame_of(9, k % 2 ? 0.6f : 0.4f, 0.5f, 0.01f);
    s.add_frame(f.view(3, 3));
  }
  const auto j = s.scores();
  EXPECT_NEAR(j["temporal_rmse"].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(j["temporal_rmse_excess"].get<double>(), std::sqrt(0.04 - 2e-4), 1e-6);
}

// Issue 42: a frame that did not change reuses frame k - 1's reference (traced once). The same
// alternating estimate as above: d = +-0.2, and with the reference repeated nothing is removed,
// so the excess is the whole 0.2 (sqrt(0.04 - 2e-4) = 0.1995 when the frames were independent).
TEST(TemporalScores, RepeatedReferenceRemovesNoNoise) {
  TemporalScorer repeated, independent;
  for (int k = 0; k < 5; ++k) {
    Frame f = frame_of(9, k % 2 ? 0.6f : 0.4f, 0.5f, 0.01f);
    TemporalFrame v = f.view(3, 3);
    independent.add_frame(v);
    v.ref_repeats_previous = k > 0;
    repeated.add_frame(v);
  }
  EXPECT_NEAR(repeated.scores()["temporal_rmse_excess"].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(independent.scores()["temporal_rmse_excess"].get<double>(), std::sqrt(0.04 - 2e-4),
              1e-6);
  // Each frame's own rmse_excess still removes its reference's noise (0.1^2 - 0.01^2).
  EXPECT_NEAR(repeated.frame_rmse_excess()[1], std::sqrt(0.01 - 1e-4), 1e-6);
}

TEST(TemporalScores, MotionReadsThePreviousFrameBilinearlyAndDisocclusionAges) {
  // A ramp est = ref = x moving right by 0.5 px per frame: reading frame k-1 at p - motion finds
  // the same values, so d = 0 (a read without motion would see 0.5 per frame).
  const int w = 8, h = 2;
  TemporalScorer s;
  for (int k = 0; k < 4; ++k) {
    Frame f = frame_of(w * h, 0.0f, 0.0f, 0.0f);
    f.motion.assign(2 * w * h, 0.0f);
    f.disoccluded.assign(w * h, 0.0f);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const int p = j * w + i;
        f.est[p] = f.ref[p] = 0.1f * (i - 0.5f * k);
        f.est[p] += 0.05f * (k == 2 && i == 3);  // one pixel wrong in frame 2
        if (k > 0) f.motion[2 * p] = 0.5f;
        if (k > 0 && i == 0) f.disoccluded[p] = 1.0f;  // the entering column
      }
    s.add_frame(f.view(w, h));
  }
  const auto j = s.scores();
  // Only frame 2's wrong pixels (column 3 of both rows) and frame 3's reads of them differ:
  // d = 0.05 at those 2 pixels in frame 2, and -0.05 * 0.5 at the 4 pixels of columns 3 and 4,
  // whose bilinear reads take half of a wrong pixel, in frame 3.
  EXPECT_GT(j["temporal_rmse"].get<double>(), 0.0);
  const double n = 3.0 * (w - 1) * h;  // frames 1..3, pixels not disoccluded
  const double expected = std::sqrt((2 * 0.05 * 0.05 + 4 * (0.025 * 0.025)) / n);
  EXPECT_NEAR(j["temporal_rmse"].get<double>(), expected, 1e-6);
  // Disoccluded pixels exist: ages are tracked and the recent-disocclusion error is exact (0).
  EXPECT_NEAR(j["disocclusion_rmse_excess"].get<double>(), 0.0, 1e-7);
  EXPECT_EQ(j["settle_frames"], 0);
}

TEST(TemporalScores, RejectsAFrameOfAnotherSize) {
  TemporalScorer s;
  Frame a = frame_of(4, 0, 0, 0), b = frame_of(6, 0, 0, 0);
  s.add_frame(a.view(2, 2));
  EXPECT_ANY_THROW(s.add_frame(b.view(3, 2)));
}

}  // namespace
}  // namespace aoeval
