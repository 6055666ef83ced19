// The temporal accumulation stage against closed forms (issue 31, "It must show" 2): a constant
// input converges to that constant with the exponent its blend factor implies, a disocclusion
// resets the history, clamping bounds a stale history, and reprojection of a translated image is
// exact at integer pixel offsets. Every expectation is computed from the stage's formulas
// (temporal_stage.h); tolerances are float rounding (values are stored as float, ~6e-8 relative,
// a few roundings per frame).
#include "estimators/temporal/temporal_stage.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scenes/random.h"

namespace aoeval {
namespace {

// A flat, fully covered w x h G-buffer facing the camera, object 0; `motion` and `disoccluded`
// filled as for a sequence frame (zero motion, nothing disoccluded).
GBuffer flat(int w, int h) {
  GBuffer g;
  g.width = w;
  g.height = h;
  const size_t n = g.pixel_count();
  g.coverage.assign(n, 1.0f);
  g.depth.assign(n, 1.0f);
  g.position.assign(n, glm::vec3(0.0f));
  g.normal.assign(n, glm::vec3(0, 0, 1));
  g.geometric_normal.assign(n, glm::vec3(0, 0, 1));
  g.object_id.assign(n, 0.0f);
  g.motion.assign(n, glm::vec2(0.0f));
  g.disoccluded.assign(n, 0.0f);
  return g;
}

TemporalSettings no_clamp(double alpha_min, int history_limit) {
  TemporalSettings s;
  s.alpha_min = alpha_min;
  s.history_limit = history_limit;
  s.clamp = false;
  return s;
}

// no_clamp(0, 32) with the anti-lag on over 5x5 windows.
TemporalSettings with_antilag(double antilag, double antilag_min, int frames) {
  TemporalSettings s = no_clamp(0.0, 32);
  s.antilag = antilag;
  s.antilag_min = antilag_min;
  s.antilag_radius = 2;
  s.antilag_frames = frames;
  return s;
}

// |mean of value() - truth| over every pixel (a flat, fully covered G-buffer): how far a history
// lags behind a truth that stepped.
double mean_bias(const TemporalAccumulator& stage, double truth) {
  double bias = 0.0;
  for (float v : stage.value()) bias += v - truth;
  return std::abs(bias / static_cast<double>(stage.value().size()));
}

// Frame 0 shows v, every later frame c: the error value - c after frame k is (v - c) times the
// product of (1 - alpha_j), j = 1..k. Three regimes of alpha_j = max(alpha_min, 1/(L_j + 1)):
// the running mean (alpha_min = 0, long limit): error (v - c) / (k + 1); the fixed-alpha regime
// from the first blend (alpha_min >= 1/2): error (v - c) (1 - alpha_min)^k exactly; and the
// hand-over from the running mean to a fixed alpha, at the first frame where 1/(L + 1) <=
// alpha_min or where the history length reaches history_limit.
TEST(TemporalStage, AConstantInputConvergesWithTheExponentOfItsBlendFactor) {
  const double v = 1.0, c = 0.25;
  const GBuffer g = flat(4, 3);
  struct Case {
    const char* regime;
    double alpha_min;
    int limit;
    double (*error)(int k);  // relative to v - c, after frame k >= 1
  };
  const Case cases[] = {
      {"running mean", 0.0, 4096, [](int k) { return 1.0 / (k + 1); }},
      {"fixed alpha 0.6", 0.6, 4096, [](int k) { return std::pow(0.4, k); }},
      // 1/(L + 1) = 1/10 at frame 9: the running mean until then, alpha = 0.1 after.
      {"alpha_min 0.1", 0.1, 4096,
       [](int k) { return k <= 9 ? 1.0 / (k + 1) : 0.1 * std::pow(0.9, k - 9); }},
      // The stored length stops at 4, so from frame 4 on alpha = 1/(4 + 1).
      {"history_limit 4", 0.0, 4,
       [](int k) { return k <= 4 ? 1.0 / (k + 1) : 0.2 * std::pow(0.8, k - 4); }},
  };
  for (const Case& cs : cases) {
    TemporalAccumulator stage(no_clamp(cs.alpha_min, cs.limit));
    stage.accumulate(g, std::vector<float>(g.pixel_count(), static_cast<float>(v)));
    for (int k = 1; k <= 24; ++k) {
      stage.accumulate(g, std::vector<float>(g.pixel_count(), static_cast<float>(c)));
      const double expected = c + (v - c) * cs.error(k);
      for (size_t p = 0; p < g.pixel_count(); ++p) {
        ASSERT_NEAR(stage.value()[p], expected, 1e-6) << cs.regime << ", frame " << k;
        ASSERT_NEAR(stage.moment1()[p], expected, 1e-6) << cs.regime << ", frame " << k;
      }
    }
    EXPECT_EQ(stage.history_length()[0], std::min(25, cs.limit)) << cs.regime;
  }
}

// A disoccluded pixel, a pixel whose history lies on another object and one whose history is off
// screen all start afresh: the value is this frame's, the history length 1; the others blend.
TEST(TemporalStage, ADisocclusionResetsTheHistory) {
  GBuffer g = flat(6, 4);
  TemporalAccumulator stage(no_clamp(0.0, 64));
  for (int k = 0; k < 3; ++k) stage.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
  ASSERT_EQ(stage.history_length()[0], 3.0f);
  g.disoccluded[g.index(1, 1)] = 1.0f;     // the G-buffer's disocclusion
  g.object_id[g.index(2, 1)] = 1.0f;       // history on another object: no valid tap
  g.motion[g.index(0, 2)] = {2.0f, 0.0f};  // from x = -1.5: off screen
  stage.accumulate(g, std::vector<float>(g.pixel_count(), 0.0f));
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      const bool afresh = p == g.index(1, 1) || p == g.index(2, 1) || p == g.index(0, 2);
      EXPECT_EQ(stage.was_reset()[p], afresh ? 1 : 0) << i << "," << j;
      EXPECT_EQ(stage.history_length()[p], afresh ? 1.0f : 4.0f) << i << "," << j;
      EXPECT_NEAR(stage.value()[p], afresh ? 0.0 : 0.75, 1e-7) << i << "," << j;
      EXPECT_NEAR(stage.moment2()[p], afresh ? 0.0 : 0.75, 1e-7) << i << "," << j;
    }
  // reset() forgets everything: the next frame is its own input.
  stage.reset();
  stage.accumulate(g, std::vector<float>(g.pixel_count(), 0.5f));
  for (float x : stage.value()) EXPECT_EQ(x, 0.5f);
}

// A history of 1 (twenty frames of 1), then a checkerboard of 0.2 and 0.4: the history is clamped
// to mu + gamma sigma of each pixel's 3x3 window before the blend, so the output is alpha x + (1 -
// alpha) min(1, mu + gamma sigma), with mu, sigma the window's population statistics (five
// squares of one colour, four of the other). Without the clamp the stale 1 survives.
TEST(TemporalStage, ClampingBoundsAStaleHistory) {
  const GBuffer g = flat(8, 8);
  std::vector<float> board(g.pixel_count());
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) board[g.index(i, j)] = (i + j) % 2 ? 0.4f : 0.2f;
  for (const double gamma : {0.5, 1.0, 2.0}) {
    TemporalSettings s = no_clamp(0.1, 32);
    s.clamp = true;
    s.gamma = gamma;
    s.clamp_radius = 1;
    TemporalAccumulator clamped(s), free_running(no_clamp(0.1, 32));
    for (int k = 0; k < 20; ++k) {
      clamped.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
      free_running.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
    }
    clamped.accumulate(g, board);
    free_running.accumulate(g, board);
    const double alpha = 0.1;  // max(0.1, 1/(20 + 1))
    for (int j = 1; j + 1 < g.height; ++j)
      for (int i = 1; i + 1 < g.width; ++i) {
        const size_t p = g.index(i, j);
        const double x = board[p], other = x == 0.2f ? 0.4f : 0.2f;  // centre: 5 like it, 4 not
        const double mu = (5.0 * x + 4.0 * other) / 9.0;
        const double sigma = std::sqrt((5.0 * x * x + 4.0 * other * other) / 9.0 - mu * mu);
        const double bound = std::min(1.0, mu + gamma * sigma);
        EXPECT_NEAR(clamped.value()[p], alpha * x + (1.0 - alpha) * bound, 1e-6) << gamma;
        EXPECT_NEAR(free_running.value()[p], alpha * x + (1.0 - alpha) * 1.0, 1e-6);
      }
  }
  // clamp_sigma_min: a flat neighbourhood (sigma = 0) still lets the history within that much.
  TemporalSettings s = no_clamp(0.5, 32);
  s.clamp = true;
  s.gamma = 1.0;
  s.clamp_sigma_min = 0.05;
  s.clamp_radius = 1;
  TemporalAccumulator stage(s);
  stage.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
  stage.accumulate(g, std::vector<float>(g.pixel_count(), 0.5f));
  for (float x : stage.value()) EXPECT_NEAR(x, 0.5 * 0.5 + 0.5 * 0.55, 1e-6);
}

// Frame 0 a random image f, frame 1 the same scene translated by (3, -2) pixels (motion (3, -2)
// everywhere) with a new random input x: at the first blend alpha = 1/2, so the value is exactly
// 0.5 x(p) + 0.5 f(p - m) where p - m is on screen, and x(p) where it is not. At a half-pixel
// offset the read is the mean of the two texels it straddles.
TEST(TemporalStage, ReprojectionOfATranslatedImageIsExactAtIntegerOffsets) {
  GBuffer g = flat(16, 12);
  const size_t n = g.pixel_count();
  std::vector<float> f(n), x(n);
  SplitMix64 rng(5);
  for (size_t p = 0; p < n; ++p) f[p] = rng.uniform_float(), x[p] = rng.uniform_float();
  for (const glm::vec2 m : {glm::vec2(3, -2), glm::vec2(0, 0), glm::vec2(-5, 4)})
    for (const HistoryRead read : {HistoryRead::bilinear, HistoryRead::catmull_rom}) {
      TemporalSettings settings = no_clamp(0.0, 32);
      settings.history_read = read;
      TemporalAccumulator stage(settings);
      stage.accumulate(g, f);
      g.motion.assign(n, m);
      stage.accumulate(g, x);
      for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i) {
          const size_t p = g.index(i, j);
          const int a = i - static_cast<int>(m.x), b = j - static_cast<int>(m.y);
          const bool on = a >= 0 && b >= 0 && a < g.width && b < g.height;
          const double h = on ? f[g.index(a, b)] : 0.0;
          const auto expected = static_cast<float>(on ? 0.5 * x[p] + 0.5 * h : x[p]);
          EXPECT_EQ(stage.value()[p], expected) << i << "," << j;
          EXPECT_EQ(stage.was_reset()[p], on ? 0 : 1);
        }
    }
  TemporalAccumulator stage(no_clamp(0.0, 32));
  g.motion.assign(n, glm::vec2(0));
  stage.accumulate(g, f);
  g.motion.assign(n, glm::vec2(0.5f, 0.0f));
  stage.accumulate(g, x);
  for (int j = 0; j < g.height; ++j)
    for (int i = 1; i < g.width; ++i) {
      const size_t p = g.index(i, j);
      const double h = 0.5 * f[g.index(i - 1, j)] + 0.5 * f[p];
      EXPECT_NEAR(stage.value()[p], 0.5 * x[p] + 0.5 * h, 1e-7);
    }
}

// A smooth image (a product of sines, period 8 pixels, amplitude 0.25 around 0.5) translated by a
// sub-pixel step every frame, the input each frame being the exact translated image: a perfect
// history read would leave the output equal to the input. Sharpness is measured as the rms error of
// the output against that exact image after 30 frames, over pixels 4 or more from the border (their
// taps stay on screen), relative to the signal's rms amplitude. A bilinear read low-passes the
// history at every fractional offset (its response at this frequency is about 0.88 a frame), so
// the accumulated image loses much of its contrast; the Catmull-Rom read keeps it.
TEST(TemporalStage, ACatmullRomHistoryStaysSharpUnderSubPixelMotion) {
  const int w = 64, h = 48, frames = 30;
  const double period = 8.0, step_x = 0.37, step_y = 0.23;
  auto image = [&](double shift_x, double shift_y) {
    std::vector<float> out(static_cast<size_t>(w) * h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const double x = i + 0.5 - shift_x, y = j + 0.5 - shift_y;
        out[static_cast<size_t>(j) * w + i] = static_cast<float>(
            0.5 + 0.25 * std::sin(2.0 * M_PI * x / period) * std::sin(2.0 * M_PI * y / period));
      }
    return out;
  };
  auto relative_error = [&](HistoryRead read) {
    TemporalSettings s = no_clamp(0.1, 32);
    s.history_read = read;
    TemporalAccumulator stage(s);
    GBuffer g = flat(w, h);
    std::vector<float> truth;
    for (int k = 0; k < frames; ++k) {
      g.motion.assign(g.pixel_count(), k ? glm::vec2(step_x, step_y) : glm::vec2(0.0f));
      truth = image(k * step_x, k * step_y);
      stage.accumulate(g, truth);
    }
    double err2 = 0.0, signal2 = 0.0;
    for (int j = 4; j < h - 4; ++j)
      for (int i = 4; i < w - 4; ++i) {
        const size_t p = g.index(i, j);
        err2 += std::pow(stage.value()[p] - truth[p], 2.0);
        signal2 += std::pow(truth[p] - 0.5, 2.0);
      }
    return std::sqrt(err2 / signal2);
  };
  const double bilinear = relative_error(HistoryRead::bilinear);
  const double catmull_rom = relative_error(HistoryRead::catmull_rom);
  std::printf("relative rms error after 30 frames: bilinear %.4f, catmull-rom %.4f\n", bilinear,
              catmull_rom);
  EXPECT_GT(bilinear, 0.3) << "the bilinear read should have blurred the history";
  EXPECT_LT(catmull_rom, 0.5 * bilinear);
}

// Anti-lag (step 5b): a still view whose truth steps from 1 to 0.5 after 21 frames (a shadow
// arriving). The windows are flat (sigma 0), so the threshold is antilag_min = 0.02 and the window
// means differ by d = 0.5: the history is moved to within the threshold of this frame's window
// mean, h = 1 - 0.5 (1 - 0.02/0.5) = 0.52, the history length read, 21, is scaled by (0.02 /
// 0.5)^2 and the blend factor is 1 / (21 (0.02/0.5)^2 + 1), where without anti-lag it is 1 / 22
// and h = 1. Over a still truth
// with noise (sigma 0.2 a pixel, 5x5 windows) it rarely fires: the error after 30 frames stays
// within 1.25 x that without it.
TEST(TemporalStage, AntiLagShortensAHistoryWhoseTruthMoved) {
  const GBuffer g = flat(12, 10);
  const TemporalSettings s = with_antilag(3.0, 0.02, 1);
  TemporalAccumulator fast(s), slow(no_clamp(0.0, 32));
  for (int k = 0; k < 21; ++k) {
    fast.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
    slow.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
  }
  fast.accumulate(g, std::vector<float>(g.pixel_count(), 0.5f));
  slow.accumulate(g, std::vector<float>(g.pixel_count(), 0.5f));
  const double len = 21.0 * (0.02 / 0.5) * (0.02 / 0.5), alpha = 1.0 / (len + 1.0);
  for (size_t p = 0; p < g.pixel_count(); ++p) {
    EXPECT_NEAR(fast.value()[p], alpha * 0.5 + (1.0 - alpha) * 0.52, 1e-6);
    EXPECT_NEAR(slow.value()[p], 0.5 / 22.0 + 21.0 / 22.0, 1e-6);
  }

  const GBuffer big = flat(48, 40);
  TemporalAccumulator guarded(s), free_running(no_clamp(0.0, 32));
  SplitMix64 rng(11);
  for (int k = 0; k < 30; ++k) {
    std::vector<float> x(big.pixel_count());
    for (float& v : x) v = 0.5f + 0.2f * (2.0f * rng.uniform_float() - 1.0f) * std::sqrt(3.0f);
    guarded.accumulate(big, x);
    free_running.accumulate(big, x);
  }
  double e_guarded = 0.0, e_free = 0.0;
  for (size_t p = 0; p < big.pixel_count(); ++p) {
    e_guarded += std::pow(guarded.value()[p] - 0.5, 2.0);
    e_free += std::pow(free_running.value()[p] - 0.5, 2.0);
  }
  EXPECT_LT(std::sqrt(e_guarded), 1.25 * std::sqrt(e_free));
}

// The tripped history's shift and length powers (antilag_shift_power K, antilag_length_power P),
// on the step above: tau / d = 0.02 / 0.5 = 0.04, the history moves by d (1 - 0.04^K), h = 1 -
// 0.5 (1 - 0.04^K), and its length read, 21, is scaled by 0.04^P. K = 1, P = 2 is the step above
// (soft thresholding: h = 0.52); K = 3, P = 1 (gtao's) takes the change nearly whole, h = 0.500032,
// with a longer history, 21 x 0.04 = 0.84 frames; P = 0 keeps the length, 21.
TEST(TemporalStage, AntiLagShiftAndLengthPowersInClosedForm) {
  const GBuffer g = flat(12, 10);
  for (const auto& [K, P] :
       std::vector<std::pair<double, double>>{{1, 2}, {3, 1}, {4, 2}, {2, 0}}) {
    TemporalSettings s = with_antilag(3.0, 0.02, 1);
    s.antilag_shift_power = K;
    s.antilag_length_power = P;
    TemporalAccumulator stage(s);
    for (int k = 0; k < 21; ++k) stage.accumulate(g, std::vector<float>(g.pixel_count(), 1.0f));
    stage.accumulate(g, std::vector<float>(g.pixel_count(), 0.5f));
    const double r = 0.02 / 0.5, h = 1.0 - 0.5 * (1.0 - std::pow(r, K));
    const double len = 21.0 * std::pow(r, P), alpha = 1.0 / (len + 1.0);
    for (size_t p = 0; p < g.pixel_count(); ++p) {
      EXPECT_NEAR(stage.value()[p], alpha * 0.5 + (1.0 - alpha) * h, 1e-6) << K << " " << P;
      EXPECT_NEAR(stage.history_length()[p], len + 1.0, 1e-5) << K << " " << P;
    }
  }
}

// Anti-lag fires on change, not on noise: over a still truth with noise (uniform, sigma 0.2 a
// pixel, 5x5 windows: a window mean's standard error e = 0.04), the history's window mean hbar
// after frame 0 is as noisy as this frame's, so f - hbar has a standard error of sqrt(2) e. With
// the threshold antilag = 2 in that unit (antilag_min 0) noise alone trips it at about the normal
// tail's rate, 2 (1 - Phi(2)) = 4.6 % (a little more: sigma is estimated from 25 pixels); a
// threshold on this frame's error alone, 2 e = 1.41 sqrt(2) e, trips 2 (1 - Phi(1.41)) = 16 %.
// Frame 1's trips are the pixels whose history length is below 2. 128 x 96 pixels are about 490
// independent windows: the share's standard error is about 0.01.
TEST(TemporalStage, AntiLagTripsOnNoiseAtTheRateItsThresholdSays) {
  const GBuffer g = flat(128, 96);
  TemporalAccumulator stage(with_antilag(2.0, 0.0, 1));
  SplitMix64 rng(21);
  for (int k = 0; k < 2; ++k) {
    std::vector<float> x(g.pixel_count());
    for (float& v : x) v = 0.5f + 0.2f * (2.0f * rng.uniform_float() - 1.0f) * std::sqrt(3.0f);
    stage.accumulate(g, x);
  }
  size_t tripped = 0;
  for (float len : stage.history_length()) tripped += len < 1.999f ? 1 : 0;
  const double share = static_cast<double>(tripped) / g.pixel_count();
  std::printf("a still view's frame 1: anti-lag tripped on %.2f %% of pixels\n", 100.0 * share);
  EXPECT_GT(share, 0.02);  // it is a test, not off
  EXPECT_LT(share, 0.09);
}

// The observed spread (antilag_spread_frames) on noise the window's own spread cannot see: a still
// truth 0.5 whose noise (uniform, sigma 0.05) is one value per 4 x 4 block and frame, as after
// gtao's 4 x 4 denoise. A 3 x 3 window holds 1 to 4 blocks, so its mean's standard error is 0.025
// to 0.05, while sigma / sqrt(n) of its pixels is at most 0.05 / 3 (0 inside a block): the
// independent-pixel noise trips the threshold antilag = 2 on most pixels (measured 69.7 %). The
// spread the difference has shown over the last 8 frames is its own variance, so the trips fall to
// at most the normal tail's 2 (1 - Phi(2)) = 4.6 % (a uniform's window mean has shorter tails;
// measured 4.3 %). A frame's trips are the pixels whose history length grew by less than 1
// (static camera, history_limit 64), counted over frames 16-23 of 768 blocks: the share's
// standard error is under 0.01 even counting whole blocks. A change still shows: a step of 0.2 at
// frame 24 lags 8 frames later by less than half of what it does without the anti-lag (measured
// 0.0048 against 0.1504).
TEST(TemporalStage, TheObservedSpreadKeepsCorrelatedNoiseFromTrippingTheAntiLag) {
  const GBuffer g = flat(128, 96);
  auto run = [&](int spread_frames, double antilag, double* trips) {
    TemporalSettings s = with_antilag(antilag, 0.0, 1);
    s.history_limit = 64;
    s.antilag_radius = 1;
    s.antilag_spread_frames = spread_frames;
    TemporalAccumulator stage(s);
    SplitMix64 rng(3);
    double tripped = 0.0, counted = 0.0, truth = 0.5;
    std::vector<float> before;
    for (int k = 0; k < 32; ++k) {
      if (k == 24) truth = 0.7;
      std::vector<float> block(32 * 24), x(g.pixel_count());
      for (float& b : block)
        b = static_cast<float>(0.05 * std::sqrt(3.0) * (2.0 * rng.uniform_float() - 1.0));
      for (int j = 0; j < g.height; ++j)
        for (int i = 0; i < g.width; ++i)
          x[g.index(i, j)] = static_cast<float>(truth + block[(j / 4) * 32 + i / 4]);
      stage.accumulate(g, x);
      if (k >= 16 && k < 24)
        for (size_t p = 0; p < g.pixel_count(); ++p, counted += 1.0)
          tripped += stage.history_length()[p] < before[p] + 0.999f ? 1.0 : 0.0;
      before = stage.history_length();
    }
    *trips = tripped / counted;
    return mean_bias(stage, truth);
  };
  double trips_model = 0.0, trips_observed = 0.0, unused = 0.0;
  const double lag_model = run(0, 2.0, &trips_model);
  const double lag_observed = run(8, 2.0, &trips_observed);
  const double lag_none = run(0, 0.0, &unused);
  std::printf(
      "correlated noise, still frames 16-23: anti-lag tripped on %.2f %% (independent-pixel "
      "noise), %.2f %% (observed spread); lag 8 frames after a 0.2 step: %.4f, %.4f (none %.4f)\n",
      100.0 * trips_model, 100.0 * trips_observed, lag_model, lag_observed, lag_none);
  EXPECT_GT(trips_model, 0.3);
  EXPECT_GT(trips_observed, 0.01);  // it is a test, not off
  EXPECT_LT(trips_observed, 0.09);
  EXPECT_LT(lag_observed, 0.5 * lag_none);
}

// Anti-lag's fast history (antilag_frames): a still, noisy view (uniform noise of sigma 0.2 a
// pixel around the truth, 5x5 windows, so one frame's window mean has a standard error of 0.04)
// whose truth steps from 0.5 to 0.4 after 24 frames. Without anti-lag the 32-frame running mean
// still lags by 0.1 x 24/32 = 0.075 eight frames later (the mean bias over the image). One
// frame's threshold, 3 x 0.04 = 0.12, is above the step, so antilag_frames = 1 sees it only
// where the noise helps; a fast history of 2 frames has a standard error of 0.04 sqrt(a / (2 -
// a)) = 0.023 (a = 1/2), a threshold of 0.07, and sees it everywhere after a frame or two: its
// lag is under 0.6 x one frame's (measured 0.017 against 0.036). Before the step (a still truth)
// both stay within 1.1 x the error of no anti-lag (measured 0.0415 and 0.0408 against 0.0408).
TEST(TemporalStage, AFastHistoryDetectsASmallerChangeThanOneFrame) {
  const GBuffer g = flat(48, 40);
  auto run = [&](double antilag, int frames, double* before) {
    const TemporalSettings s = with_antilag(antilag, 0.0, frames);
    TemporalAccumulator stage(s);
    SplitMix64 rng(5);
    double truth = 0.5;
    for (int k = 0; k < 32; ++k) {
      if (k == 24) {
        double e2 = 0.0;
        for (float v : stage.value()) e2 += (v - truth) * (v - truth);
        *before = std::sqrt(e2 / g.pixel_count());
        truth = 0.4;
      }
      std::vector<float> x(g.pixel_count());
      for (float& v : x)
        v = static_cast<float>(truth + 0.2 * std::sqrt(3.0) * (2.0 * rng.uniform_float() - 1.0));
      stage.accumulate(g, x);
    }
    return mean_bias(stage, truth);
  };
  double still_none = 0.0, still_one = 0.0, still_fast = 0.0;
  const double lag_none = run(0.0, 1, &still_none);
  const double lag_one = run(3.0, 1, &still_one);
  const double lag_fast = run(3.0, 2, &still_fast);
  std::printf(
      "lag 8 frames after a 0.1 step: none %.4f, one frame %.4f, fast history %.4f; still "
      "error %.4f %.4f (none %.4f)\n",
      lag_none, lag_one, lag_fast, still_one, still_fast, still_none);
  EXPECT_NEAR(lag_none, 0.075, 0.005);
  EXPECT_LT(lag_one, lag_none);
  EXPECT_LT(lag_fast, 0.6 * lag_one);
  EXPECT_LT(still_one, 1.1 * still_none);
  EXPECT_LT(still_fast, 1.1 * still_none);
}

// The anti-lag shift at the edge of a change: columns 0..23 stay at 1 while columns 24..47 brighten
// from 0.4 to 1 at frame 16, so the window means of columns 22 and 23 rise by up to 0.24 while
// their own history is already 1. Shifted by that rise, their history left [0, 1] (1.0019 on
// dragon/walk with gtao's tuned defaults, which the harness refuses); it must stay an AO value.
TEST(TemporalStage, TheAntiLagShiftKeepsTheHistoryAnAoValue) {
  const GBuffer g = flat(48, 40);
  const TemporalSettings s = with_antilag(1.6, 0.08, 2);
  TemporalAccumulator stage(s);
  float highest = 0.0f;
  for (int k = 0; k < 24; ++k) {
    std::vector<float> x(g.pixel_count());
    for (size_t p = 0; p < x.size(); ++p)
      x[p] = static_cast<int>(p % 48) < 24 || k >= 16 ? 1.0f : 0.4f;
    stage.accumulate(g, x);
    for (float v : stage.value()) highest = std::max(highest, v);
  }
  EXPECT_LE(highest, 1.0f);
  // It still follows the change: the brightened half reaches its new truth.
  EXPECT_NEAR(stage.value()[20 * 48 + 40], 1.0f, 0.02f);
}

// The same inputs give the same bits on one thread and on many.
TEST(TemporalStage, SameBitsWhateverTheThreadCount) {
  GBuffer g = flat(32, 24);
  std::vector<float> a(g.pixel_count()), b(g.pixel_count());
  SplitMix64 rng(9);
  for (size_t p = 0; p < a.size(); ++p) a[p] = rng.uniform_float(), b[p] = rng.uniform_float();
  g.motion.assign(g.pixel_count(), glm::vec2(0.3f, -1.7f));
  TemporalSettings s = no_clamp(0.05, 32);
  s.clamp = true;
  s.gamma = 1.0;
  s.clamp_radius = 2;
  auto run = [&] {
    TemporalAccumulator stage(s);
    stage.accumulate(g, a);
    stage.accumulate(g, b);
    stage.accumulate(g, a);
    return stage.value();
  };
  std::vector<float> one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = run();
  }
  EXPECT_EQ(run(), one);
}

// The fragment declares every setting once; temporal_settings() reads them all back.
TEST(TemporalStage, TheParameterFragmentRoundTrips) {
  const std::vector<ParamSpec> specs = temporal_params();
  ASSERT_EQ(specs.size(), 14u);
  const ParamSet p = resolve_params("test", specs,
                                    {{"history_read", "bilinear"},
                                     {"history_limit", 8},
                                     {"alpha_min", 0.2},
                                     {"clamp", false},
                                     {"gamma", 1.5},
                                     {"clamp_sigma_min", 0.1},
                                     {"clamp_radius", 3},
                                     {"antilag", 2.5},
                                     {"antilag_min", 0.03},
                                     {"antilag_radius", 4},
                                     {"antilag_frames", 6},
                                     {"antilag_spread_frames", 5},
                                     {"antilag_shift_power", 3.5},
                                     {"antilag_length_power", 1.5}},
                                    "test");
  const TemporalSettings s = temporal_settings(p);
  EXPECT_EQ(s.history_read, HistoryRead::bilinear);
  EXPECT_EQ(s.history_limit, 8);
  EXPECT_EQ(s.alpha_min, 0.2);
  EXPECT_FALSE(s.clamp);
  EXPECT_EQ(s.gamma, 1.5);
  EXPECT_EQ(s.clamp_sigma_min, 0.1);
  EXPECT_EQ(s.clamp_radius, 3);
  EXPECT_EQ(s.antilag, 2.5);
  EXPECT_EQ(s.antilag_min, 0.03);
  EXPECT_EQ(s.antilag_radius, 4);
  EXPECT_EQ(s.antilag_frames, 6);
  EXPECT_EQ(s.antilag_spread_frames, 5);
  EXPECT_EQ(s.antilag_shift_power, 3.5);
  EXPECT_EQ(s.antilag_length_power, 1.5);
  EXPECT_EQ(temporal_params({.history_limit = 12})[1].default_value, 12);
  EXPECT_EQ(temporal_params().front().default_value, "catmull-rom");
}

}  // namespace
}  // namespace aoeval
