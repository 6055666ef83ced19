// The sequence scores (temporal.h) on synthetic frames whose answer is known exactly.
#include "harness/scoring/temporal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
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

// seq_rmse_excess_sd and temporal_rmse_excess_sd (issue 42): the spread over independent draws of
// the references' noise. An estimate that flickers (0.65 and 0.55 in turn, against a truth of
// 0.6, on half of the pixels, where the reference's stderr is 0.04; the other half exact and
// noiseless) over 8 frames, each frame with a reference of its own or all frames sharing frame
// 0's (a static view, traced once). Over 600 draws the keys' spread matches their _sd within 4
// standard errors of a standard deviation (12 %): the temporal key only with the covariance of
// neighbouring frame pairs, which share a frame's reference (without it, 1.3 x too small).
TEST(TemporalScores, SdKeysAreTheSpreadOverReferenceDraws) {
  const int n = 400, frames = 8, draws = 600;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const bool shared : {false, true}) {
    std::vector<double> seq, temporal;
    double seq_sd = 0.0, temporal_sd = 0.0;
    for (int draw = 0; draw < draws; ++draw) {
      TemporalScorer scorer;
      std::vector<float> noise(n);
      for (int k = 0; k < frames; ++k) {
        Frame f = frame_of(n, 0.6f, 0.6f, 0.0f);
        for (int p = 0; p < n; ++p) {
          if (p % 2) continue;
          f.est[p] = k % 2 ? 0.55f : 0.65f;
          f.stderr_[p] = 0.04f;
          if (k == 0 || !shared) noise[p] = static_cast<float>(0.04 * normal(rng));
          f.ref[p] = 0.6f + noise[p];
        }
        TemporalFrame v = f.view(20, 20);
        v.ref_repeats_previous = shared && k > 0;
        scorer.add_frame(v);
      }
      const auto j = scorer.scores();
      seq.push_back(j["seq_rmse_excess"].get<double>());
      seq_sd += j["seq_rmse_excess_sd"].get<double>() / draws;
      if (!shared) {
        temporal.push_back(j["temporal_rmse_excess"].get<double>());
        temporal_sd += j["temporal_rmse_excess_sd"].get<double>() / draws;
      } else {
        EXPECT_EQ(j["temporal_rmse_excess_sd"].get<double>(), 0.0);  // the differences hold none
      }
    }
    auto spread = [&](const std::vector<double>& v) {
      double mean = 0.0, var = 0.0;
      for (double x : v) mean += x / v.size();
      for (double x : v) var += (x - mean) * (x - mean) / (v.size() - 1);
      return std::sqrt(var);
    };
    const double tol = 4.0 / std::sqrt(2.0 * draws);
    EXPECT_NEAR(seq_sd, spread(seq), tol * spread(seq)) << (shared ? "shared" : "independent");
    if (!shared) {
      EXPECT_NEAR(temporal_sd, spread(temporal), tol * spread(temporal));
    }
    std::printf("%s: seq spread %.3g sd %.3g; temporal spread %.3g sd %.3g\n",
                shared ? "shared" : "independent", spread(seq), seq_sd,
                temporal.empty() ? 0.0 : spread(temporal), temporal_sd);
  }
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
  // 4 frames: no trajectory is followed from its disocclusion through age 12, so settle_frames
  // has nothing to pool (CONTRACT §10: blank when no trajectory qualifies).
  EXPECT_TRUE(j["settle_frames"].is_null());
}

// A pattern translating right by one pixel a frame (a camera panning over a still floor): column 0
// is disoccluded every frame, and the point at pixel i of frame k entered at frame k - i, so its
// age is i (frame 0's points have none). The estimate's error is a function of the point's age:
// settle_frames is read off the trajectories that the scorer follows through the motion.
struct Pan {
  int w = 16, h = 256, frames = 20;
  float ref_of(int i, int j, int k) const {
    return 0.3f + 0.02f * ((i - k + 1000) % 7) + 0.001f * j;
  }
};

double run_pan(const Pan& pan, const std::function<float(int age, int i, int j, int k)>& err,
               nlohmann::json* out = nullptr) {
  TemporalScorer s;
  for (int k = 0; k < pan.frames; ++k) {
    Frame f = frame_of(pan.w * pan.h, 0.0f, 0.0f, 0.0f);
    f.motion.assign(2 * pan.w * pan.h, 0.0f);
    f.disoccluded.assign(pan.w * pan.h, 0.0f);
    for (int j = 0; j < pan.h; ++j)
      for (int i = 0; i < pan.w; ++i) {
        const int p = j * pan.w + i;
        const int age = k - i >= 1 ? i : -1;  // entered at frame k - i; frame 0's points: none
        f.ref[p] = pan.ref_of(i, j, k);
        f.est[p] = f.ref[p] + err(age, i, j, k);
        if (k > 0) f.motion[2 * p] = 1.0f;
        if (k > 0 && i == 0) f.disoccluded[p] = 1.0f;
      }
    s.add_frame(f.view(pan.w, pan.h));
  }
  if (out) *out = s.scores();
  const auto j = s.scores();
  return j["settle_frames"].is_null() ? -1.0 : j["settle_frames"].get<double>();
}

TEST(TemporalScores, SettleIsZeroWithoutHistoryOnAPan) {
  // constant: a fixed value whatever the age; raytraced: independent noise every frame (its own
  // seed, about 1 ray's spread and 4 rays'). None keeps history, so each settles at age 0.
  const Pan pan;
  EXPECT_EQ(run_pan(pan, [&](int, int i, int j, int k) { return 0.7f - pan.ref_of(i, j, k); }), 0);
  for (const float spread : {0.25f, 0.125f}) {
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, spread);
    EXPECT_EQ(run_pan(pan, [&](int, int, int, int) { return noise(rng); }), 0) << spread;
  }
}

TEST(TemporalScores, SettleFollowsTheTrajectoriesThroughMotion) {
  // The error is 0.4 for ages 0..2 and 0.1 from age 3 on (signs alternating by row so nothing
  // cancels): settle_frames = 3 exactly. Frame 0's points (age -1) carry a large error that must
  // not reach any trajectory; were the scorer to follow pixels instead of points, ages would mix.
  const Pan pan;
  nlohmann::json j;
  run_pan(
      pan,
      [](int age, int, int row, int) {
        const float sign = row % 2 ? 1.0f : -1.0f;
        return sign * (age < 0 ? 0.9f : age < 3 ? 0.4f : 0.1f);
      },
      &j);
  EXPECT_EQ(j["settle_frames"], 3);
  // By age: 0.4 at ages 0..2, 0.1 after.
  // (The error at age 8 and over 9..12 is 0.1: never settling would read 9.)
  nlohmann::json never;
  run_pan(
      pan,
      [](int age, int, int row, int) { return (row % 2 ? 1.0f : -1.0f) * (age < 9 ? 0.4f : 0.1f); },
      &never);
  EXPECT_EQ(never["settle_frames"], 9);
}

TEST(TemporalScores, SettleSkipsTrajectoriesWhoseTruthMoves) {
  // The reference darkens along every trajectory by 0.1 over 12 frames (a shadow arriving): no
  // trajectory has a truth that holds still, so settle_frames is blank.
  Pan pan;
  TemporalScorer s;
  for (int k = 0; k < pan.frames; ++k) {
    Frame f = frame_of(pan.w * pan.h, 0.5f, 0.5f, 0.0f);
    f.motion.assign(2 * pan.w * pan.h, 1.0f);
    f.disoccluded.assign(pan.w * pan.h, 0.0f);
    for (int p = 0; p < pan.w * pan.h; ++p) {
      f.ref[p] = 0.8f - 0.01f * k;
      f.motion[2 * p + 1] = 0.0f;
      if (k > 0 && p % pan.w == 0) f.disoccluded[p] = 1.0f;
    }
    s.add_frame(f.view(pan.w, pan.h));
  }
  EXPECT_TRUE(s.scores()["settle_frames"].is_null());
  EXPECT_TRUE(s.settle_excess_by_age().empty());
}

// A still camera over a floor; a shadow's edge sweeps right one pixel a frame: ref = 0.4 left of
// column k, 0.8 elsewhere (stderr 0.01). The estimate is an exponential history of the truth
// (alpha 0.5), so it lags behind the edge; row 0's still part is wrong by 0.3 besides. Calls
// `lagging(p, err)` for each frame k's pixel p that lag_rmse_excess must count: its truth changed
// since k - 4 by more than 0.05 + 3 sqrt(se^2 + se^2) (columns k - 4 .. k - 1).
constexpr int kEdgeW = 24, kEdgeH = 4;
constexpr float kEdgeStderr = 0.01f;
void sweep_shadow_edge(TemporalScorer& s, const std::function<void(int, double)>& lagging) {
  const int w = kEdgeW, h = kEdgeH, frames = 16;
  std::vector<float> est(w * h, 0.8f);
  for (int k = 0; k < frames; ++k) {
    Frame f = frame_of(w * h, 0.0f, 0.0f, kEdgeStderr);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const int p = j * w + i;
        f.ref[p] = i < k ? 0.4f : 0.8f;
        est[p] = k == 0 ? f.ref[p] : 0.5f * f.ref[p] + 0.5f * est[p];
        f.est[p] = est[p] + (j == 0 ? 0.3f : 0.0f) * (i >= k);  // row 0's still part is wrong
        const float before = i < k - 4 ? 0.4f : 0.8f;
        if (k >= 4 && std::abs(f.ref[p] - before) > 0.05 + 3.0 * std::sqrt(2.0) * kEdgeStderr)
          lagging(p, static_cast<double>(f.est[p]) - f.ref[p]);
      }
    s.add_frame(f.view(w, h));
  }
}

// The edge above: lag_rmse_excess is the rms excess error over exactly the lagging pixels; the
// rest (including the still region with a large constant error) must not count.
TEST(TemporalScores, LagIsTheErrorWhereTheTruthMovedUnderAStillSurface) {
  TemporalScorer s;
  double err2 = 0.0, noise = 0.0, n = 0.0;
  sweep_shadow_edge(s, [&](int, double e) {
    err2 += e * e;
    noise += static_cast<double>(kEdgeStderr) * kEdgeStderr;
    n += 1.0;
  });
  ASSERT_GT(n, 0.0);
  const double expected = std::sqrt((err2 - noise) / n);
  EXPECT_GT(expected, 0.05);
  EXPECT_NEAR(s.scores()["lag_rmse_excess"].get<double>(), expected, 1e-9);
  EXPECT_TRUE(s.scores()["settle_frames"].is_null()) << "nothing was disoccluded";
}

TEST(TemporalScores, LagFollowsTheSurfaceAndIsBlankOverAStillScene) {
  // A camera panning over a floor (motion -1: the floor point under pixel i of frame k is x = i +
  // k; the entering column at the right is disoccluded) while a shadow's edge sweeps over the floor
  // at two points a frame (shadowed: x < 2k, so on screen i < k). Along a trajectory the truth
  // changed between k - 4 and k where 2k - 8 <= x < 2k; a scorer that compared pixels instead of
  // points would take columns k - 4 .. k - 1 only. The estimate has caught up (0.4) left of column
  // k - 4: the followed set mixes errors 0 and 0.4, the wrong one sees 0.4 only.
  const int w = 24, h = 4, frames = 16;
  const float se = 0.01f;
  TemporalScorer s;
  double err2 = 0.0, noise = 0.0, n = 0.0;
  for (int k = 0; k < frames; ++k) {
    Frame f = frame_of(w * h, 0.0f, 0.0f, se);
    f.motion.assign(2 * w * h, 0.0f);
    f.disoccluded.assign(w * h, 0.0f);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const int p = j * w + i, x = i + k;
        f.ref[p] = x < 2 * k ? 0.4f : 0.8f;
        f.est[p] = i < k - 4 ? 0.4f : 0.8f;
        if (k > 0) f.motion[2 * p] = -1.0f;
        if (k > 0 && i == w - 1) f.disoccluded[p] = 1.0f;
        if (k >= 4 && (x < 2 * k) != (x < 2 * k - 8)) {
          const double e = static_cast<double>(f.est[p]) - f.ref[p];
          err2 += e * e;
          noise += static_cast<double>(se) * se;
          n += 1.0;
        }
      }
    s.add_frame(f.view(w, h));
  }
  const double expected = std::sqrt((err2 - noise) / n);
  EXPECT_LT(expected, 0.35) << "the followed set mixes caught-up pixels in";
  EXPECT_NEAR(s.scores()["lag_rmse_excess"].get<double>(), expected, 1e-9);

  // A still camera over a still (noisy) scene: no truth moved, the key is blank.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> jitter(-0.02f, 0.02f);
  TemporalScorer still;
  for (int k = 0; k < frames; ++k) {
    Frame f = frame_of(w * h, 0.5f, 0.6f, 0.01f);
    for (float& r : f.ref) r += jitter(rng);
    still.add_frame(f.view(w, h));
  }
  EXPECT_TRUE(still.scores()["lag_rmse_excess"].is_null());
}

// The maps say where: the alternating estimate flickers 0.2 at every pixel (frame 0 has no d);
// the sweeping shadow edge (sweep_shadow_edge) leaves its lag only in the columns the edge
// crossed within the last 4 frames (the trail), each pixel its own rms excess, and none (NaN)
// in the still part, whose large constant error is not lag.
TEST(TemporalScores, MapsHoldEachPixelsFlickerAndLag) {
  TemporalScorer flicker;
  for (int k = 0; k < 5; ++k) {
    Frame f = frame_of(9, k % 2 ? 0.6f : 0.4f, 0.5f, 0.0f);
    flicker.add_frame(f.view(3, 3));
  }
  const std::vector<float> fm = flicker.flicker_map();
  ASSERT_EQ(fm.size(), 9u);
  for (float v : fm) EXPECT_NEAR(v, 0.2, 1e-6);

  const int w = kEdgeW, h = kEdgeH;
  TemporalScorer s;
  std::vector<double> err2(w * h, 0.0), n(w * h, 0.0);
  sweep_shadow_edge(s, [&](int p, double e) {
    err2[p] += e * e - static_cast<double>(kEdgeStderr) * kEdgeStderr;
    n[p] += 1.0;
  });
  const std::vector<float> lm = s.lag_map();
  ASSERT_EQ(lm.size(), static_cast<size_t>(w * h));
  int lagging = 0;
  for (int p = 0; p < w * h; ++p) {
    if (n[p] == 0.0) {
      EXPECT_TRUE(std::isnan(lm[p])) << "pixel " << p;
      continue;
    }
    ++lagging;
    EXPECT_NEAR(lm[p], std::sqrt(std::max(0.0, err2[p] / n[p])), 1e-6) << "pixel " << p;
  }
  EXPECT_GT(lagging, 0);
  EXPECT_TRUE(std::isnan(lm[w - 1])) << "the edge never reached the last column";
}

TEST(TemporalScores, RejectsAFrameOfAnotherSize) {
  TemporalScorer s;
  Frame a = frame_of(4, 0, 0, 0), b = frame_of(6, 0, 0, 0);
  s.add_frame(a.view(2, 2));
  EXPECT_ANY_THROW(s.add_frame(b.view(3, 2)));
}

// A non-finite motion vector on a compared pixel is refused, not followed: a NaN one read frame
// k - 1 at an undefined index (a SIGSEGV in compare --sequence). read_gbuffer refuses such files
// first; this is the guard for every other caller.
TEST(TemporalScores, RejectsNonFiniteMotionNamingThePixel) {
  for (const float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    TemporalScorer s;
    Frame a = frame_of(6, 0.5f, 0.5f, 0.0f), b = frame_of(6, 0.5f, 0.5f, 0.0f);
    s.add_frame(a.view(3, 2));
    b.motion.assign(12, 0.0f);
    b.motion[2 * 4 + 1] = bad;  // pixel (1, 1), y
    try {
      s.add_frame(b.view(3, 2));
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::exception& e) {
      EXPECT_STREQ(e.what(), "sequence frame 1: motion at pixel (1, 1) is not finite");
    }
  }
}

}  // namespace
}  // namespace aoeval
