// Known-answer tests of the image-comparison metrics (metrics.h) and of LDR-FLIP (flip.h).
#include "harness/scoring/metrics.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "base/errors.h"
#include "harness/scoring/flip.h"

namespace aoeval {
namespace {

struct Image {
  int width, height;
  std::vector<float> px;
  Image(int w, int h, float v = 0.0f) : width(w), height(h), px(static_cast<size_t>(w) * h, v) {}
  float& at(int i, int j) { return px[static_cast<size_t>(j) * width + i]; }
  ImageView view() const { return {width, height, px.data()}; }
};

Image ramp(int w, int h) {  // values k/256 for pixel k, k < 128: dyadic, exact in float
  Image im(w, h);
  for (size_t k = 0; k < im.px.size(); ++k) im.px[k] = static_cast<float>(k % 128) / 256.0f;
  return im;
}

Image offset(const Image& a, float c) {
  Image b = a;
  for (float& v : b.px) v += c;
  return b;
}

Metrics score(const Image& ref, const Image& est, const std::vector<uint8_t>& mask = {},
              const std::vector<float>& sd = {}) {
  return compare_images(ref.view(), est.view(), mask, sd);
}

double flip_mean(const Image& ref, const Image& est) {
  return score(ref, est).flip_mean;
}

TEST(Metrics, ConstantOffsetKnownAnswers) {
  const Image ref = ramp(40, 30);
  const double c = 0.0625;
  const Metrics m = score(ref, offset(ref, static_cast<float>(c)));
  EXPECT_EQ(m.pixels, 1200u);
  EXPECT_NEAR(m.bias, c, 1e-9);
  EXPECT_NEAR(m.rmse, c, 1e-9);
  EXPECT_NEAR(m.mae, c, 1e-9);
  EXPECT_NEAR(m.max_abs, c, 1e-9);
  EXPECT_NEAR(m.p95_abs, c, 1e-9);
  EXPECT_NEAR(m.psnr, -20.0 * std::log10(c), 1e-9);
  EXPECT_EQ(m.ref_stderr_rms, 0.0);
  EXPECT_NEAR(m.rmse_excess, c, 1e-9);
  const Metrics neg = score(ref, offset(ref, static_cast<float>(-c)));
  EXPECT_NEAR(neg.bias, -c, 1e-9);
  EXPECT_NEAR(neg.mae, c, 1e-9);
}

TEST(Metrics, IdenticalImages) {
  const Image ref = ramp(48, 32);
  const Metrics m = score(ref, ref);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.p95_abs, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr) && m.psnr > 0);
  EXPECT_NEAR(m.ssim, 1.0, 1e-12);
  EXPECT_EQ(m.flip_mean, 0.0);
  const nlohmann::json j = to_json(m);
  EXPECT_TRUE(j.at("psnr").is_null());
  EXPECT_EQ(j.at("ssim").get<double>(), m.ssim);
}

TEST(Metrics, MaskSetsPixelCount) {
  const Image ref = ramp(20, 10);
  Image est = offset(ref, 0.25f);
  std::vector<uint8_t> mask(200, 0);
  size_t expected = 0;
  for (size_t p = 0; p < mask.size(); ++p)
    if (p % 3 == 0 || p % 7 == 0) mask[p] = 7, ++expected;  // any nonzero value counts
  // Outside the mask anything goes, NaN included.
  for (size_t p = 0; p < mask.size(); ++p)
    if (!mask[p]) est.px[p] = std::numeric_limits<float>::quiet_NaN();
  const Metrics m = score(ref, est, mask);
  EXPECT_EQ(m.pixels, expected);
  EXPECT_NEAR(m.bias, 0.25, 1e-9);
  EXPECT_TRUE(std::isfinite(m.ssim));
  EXPECT_TRUE(std::isfinite(m.flip_mean));
}

TEST(Metrics, AlternatingOffsetHasNoBias) {
  const Image ref(16, 16, 0.5f);
  Image est = ref;
  const float c = 0.125f;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) est.at(i, j) += (i + j) % 2 ? c : -c;
  const Metrics m = score(ref, est);
  EXPECT_NEAR(m.bias, 0.0, 1e-12);
  EXPECT_NEAR(m.rmse, c, 1e-9);
  EXPECT_NEAR(m.mae, c, 1e-9);
}

TEST(Metrics, P95NearestRankOnRamp) {
  // |d| = k / 1000 for k = 1..200 (in a 20x10 image): nearest rank ceil(0.95 * 200) = 190.
  Image ref(20, 10, 0.0f), est(20, 10, 0.0f);
  for (size_t k = 0; k < 200; ++k) est.px[(k * 37) % 200] = static_cast<float>(k + 1) / 1000.0f;
  const Metrics m = score(ref, est);
  EXPECT_NEAR(m.p95_abs, 190.0f / 1000.0f, 1e-12);
  EXPECT_NEAR(m.max_abs, 200.0f / 1000.0f, 1e-12);
  // n = 7: ceil(6.65) = 7, the largest; n = 20: ceil(19) = 19.
  std::vector<uint8_t> mask(200, 0);
  for (size_t k = 0; k < 7; ++k) mask[(k * 37) % 200] = 1;
  EXPECT_NEAR(score(ref, est, mask).p95_abs, 7.0f / 1000.0f, 1e-12);
  for (size_t k = 0; k < 20; ++k) mask[(k * 37) % 200] = 1;
  EXPECT_NEAR(score(ref, est, mask).p95_abs, 19.0f / 1000.0f, 1e-12);
}

TEST(Metrics, MedianAbsNearestRankOnRampAndOneOutlier) {
  // |d| = k / 1000 for k = 1..200: nearest rank ceil(0.5 * 200) = 100; n = 7: ceil(3.5) = 4.
  Image ref(20, 10, 0.0f), est(20, 10, 0.0f);
  for (size_t k = 0; k < 200; ++k) est.px[(k * 37) % 200] = static_cast<float>(k + 1) / 1000.0f;
  const Metrics m = score(ref, est);
  EXPECT_NEAR(m.median_abs, 100.0f / 1000.0f, 1e-12);
  EXPECT_NEAR(m.p95_abs, 190.0f / 1000.0f, 1e-12);  // unchanged by the second partition
  std::vector<uint8_t> mask(200, 0);
  for (size_t k = 0; k < 7; ++k) mask[(k * 37) % 200] = 1;
  EXPECT_NEAR(score(ref, est, mask).median_abs, 4.0f / 1000.0f, 1e-12);
  // A halo of a few bad pixels moves mae but not the median: 99 pixels off by 0.01, one by 0.9.
  Image a(10, 10, 0.5f), b = offset(a, 0.01f);
  b.at(3, 3) = 0.5f + 0.4f;
  const Metrics h = score(a, b);
  EXPECT_NEAR(h.median_abs, 0.01, 1e-6);
  EXPECT_NEAR(h.mae, (99 * 0.01 + 0.4) / 100.0, 1e-6);
  // One compared pixel: the median is its error.
  std::vector<uint8_t> one(100, 0);
  one[33] = 1;
  EXPECT_NEAR(score(a, b, one).median_abs, 0.4, 1e-6);
}

TEST(Metrics, StderrAndExcess) {
  const Image ref(10, 10, 0.5f);
  const Image est = offset(ref, 0.5f);  // rmse 0.5
  const std::vector<float> sd(100, 0.375f);
  const Metrics m = score(ref, est, {}, sd);
  EXPECT_NEAR(m.ref_stderr_rms, 0.375, 1e-12);
  EXPECT_NEAR(m.rmse_excess, std::sqrt(0.25 - 0.375 * 0.375), 1e-12);
  std::vector<float> big(100, 0.0f);  // mixed stderr: mean square 0.5 * 1^2 > rmse^2
  for (size_t p = 0; p < 100; p += 2) big[p] = 1.0f;
  const Metrics e = score(ref, est, {}, big);
  EXPECT_NEAR(e.ref_stderr_rms, std::sqrt(0.5), 1e-12);
  EXPECT_EQ(e.rmse_excess, 0.0);
}

// rmse_excess_sd (issue 42): the spread of rmse_excess over independent draws of the reference's
// noise. Half the pixels are open (no error, no noise: a bounded definition's pixels with nothing
// within dmax), half sit in a crease with error 0.06 and stderr 0.03, so the error concentrates
// where the reference is noisy. Over 1000 draws the spread of rmse_excess matches each draw's
// rmse_excess_sd within 4 standard errors of a standard deviation (9 %), while the rule from the
// row's rms values alone (s = ref_stderr_rms, N = pixels: sigma = s sqrt(D^2 + s^2/2) / (D
// sqrt(N))) is about 1.4x too small here.
TEST(Metrics, ExcessSdIsTheSpreadOverReferenceDraws) {
  const int w = 40, h = 25, draws = 1000;
  Image truth(w, h), est(w, h);
  std::vector<float> sd(static_cast<size_t>(w) * h, 0.0f);
  for (size_t k = 0; k < truth.px.size(); ++k) {
    truth.px[k] = 0.7f;
    const bool crease = k % 2 == 0;
    est.px[k] = crease ? 0.76f : 0.7f;
    sd[k] = crease ? 0.03f : 0.0f;
  }
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> excess;
  double mean_sd = 0.0, rule = 0.0;
  for (int draw = 0; draw < draws; ++draw) {
    Image ref = truth;
    for (size_t k = 0; k < ref.px.size(); ++k) ref.px[k] += static_cast<float>(sd[k] * normal(rng));
    const Metrics m = score(ref, est, {}, sd);
    excess.push_back(m.rmse_excess);
    mean_sd += m.rmse_excess_sd / draws;
    const double s = m.ref_stderr_rms, d = m.rmse_excess, n = static_cast<double>(m.pixels);
    rule += s * std::sqrt(d * d + 0.5 * s * s) / (d * std::sqrt(n)) / draws;
  }
  double mean = 0.0, var = 0.0;
  for (double v : excess) mean += v / draws;
  for (double v : excess) var += (v - mean) * (v - mean) / (draws - 1);
  const double spread = std::sqrt(var);
  EXPECT_NEAR(mean_sd, spread, 4.0 * spread / std::sqrt(2.0 * draws)) << "mean " << mean;
  EXPECT_LT(rule, spread / 1.3) << "the rms rule";
  std::printf("rmse_excess %.5f: spread %.3g, rmse_excess_sd %.3g, rms rule %.3g\n", mean, spread,
              mean_sd, rule);
}

TEST(Metrics, ExcessSdIsZeroWithoutStderrAndInTheJson) {
  const Image ref = ramp(8, 8), est = offset(ramp(8, 8), 0.1f);
  EXPECT_EQ(score(ref, est).rmse_excess_sd, 0.0);
  const Metrics m = score(ref, est, {}, std::vector<float>(64, 0.01f));
  // Uniform error 0.1 and stderr 0.01: V = (4 (0.01 - 1e-4) 1e-4 + 2 1e-8) / 64.
  const double v = (4.0 * (0.01 - 1e-4) * 1e-4 + 2.0 * 1e-8) / 64.0;
  EXPECT_NEAR(m.rmse_excess_sd, std::sqrt(v) / (2.0 * m.rmse_excess), 1e-9);
  EXPECT_NEAR(to_json(m, "true_")["true_rmse_excess_sd"].get<double>(), m.rmse_excess_sd, 1e-15);
}

TEST(Metrics, SsimOfConstantImagesMatchesClosedForm) {
  const double x = 0.8, y = 0.4, c1 = 1e-4;  // est = ref scaled by 0.5
  const Metrics m = score(Image(32, 24, 0.8f), Image(32, 24, 0.4f));
  const double expected = (2 * x * y + c1) / (x * x + y * y + c1);
  EXPECT_NEAR(m.ssim, expected, 1e-6);  // float inputs: 0.8f, 0.4f
  const Image r = ramp(32, 24);
  Image half = r;
  for (float& v : half.px) v *= 0.5f;
  EXPECT_LT(score(r, half).ssim, 1.0);
}

TEST(Metrics, SsimCheckerboardVersusInverseIsStronglyNegative) {
  Image a(32, 32), b(32, 32);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i)
      a.at(i, j) = (i + j) % 2 ? 1.0f : 0.0f, b.at(i, j) = 1.0f - a.at(i, j);
  EXPECT_LT(score(a, b).ssim, -0.9);
}

TEST(Metrics, SsimMaskIgnoresUncomparedPixels) {
  // A mask excluding the right half: whatever lies there cannot change the metrics.
  const Image ref = ramp(40, 20);
  Image e1 = offset(ref, 0.05f), e2 = e1;
  std::vector<uint8_t> mask(800, 0);
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) mask[j * 40 + i] = 1;
  for (int j = 0; j < 20; ++j)
    for (int i = 20; i < 40; ++i) e1.at(i, j) = 1.0f, e2.at(i, j) = (i * j) % 3 ? 0.0f : 5.0f;
  const Metrics a = score(ref, e1, mask), b = score(ref, e2, mask);
  EXPECT_EQ(a.ssim, b.ssim);
  EXPECT_EQ(a.flip_mean, b.flip_mean);
  EXPECT_EQ(a.pixels, 400u);
}

TEST(Flip, ViewingCondition) {
  EXPECT_NEAR(flip::pixels_per_degree(), 3840.0 * M_PI / 180.0, 1e-12);  // 67.02
}

TEST(Flip, BlackVersusWhiteMatchesClosedForm) {
  // Constant images: no features, so FLIP = the re-mapped colour error of dL* = 100.
  // cmax from the published CIELAB of sRGB green (87.7347, -86.1827, 83.1793) and blue
  // (32.3026, 79.1967, -107.8637), Hunt-adjusted (a, b scaled by L / 100).
  const double gl = 87.7347, ga = -86.1827 * gl / 100, gb = 83.1793 * gl / 100;
  const double bl = 32.3026, ba = 79.1967 * bl / 100, bb = -107.8637 * bl / 100;
  const double cmax = std::pow(std::abs(gl - bl) + std::hypot(ga - ba, gb - bb), 0.7);
  const double e = std::pow(100.0, 0.7);
  const double expected = 0.95 + (e - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05;
  const double f = flip_mean(Image(24, 24, 0.0f), Image(24, 24, 1.0f));
  EXPECT_NEAR(f, expected, 1e-4);
  EXPECT_GT(f, 0.95);
  EXPECT_LT(f, 1.0);
  EXPECT_EQ(f, flip_mean(Image(24, 24, 1.0f), Image(24, 24, 0.0f)));  // symmetric
}

TEST(Flip, SmallConstantOffsetMatchesClosedForm) {
  // dL* between grey 0.5 and 0.52 (linear luminance), below pc cmax: linear branch.
  auto lstar = [](double t) { return 116.0 * std::cbrt(t) - 16.0; };
  const double cmax = 41.2566;  // as above, to 4 decimals
  const double e = std::pow(lstar(0.52) - lstar(0.5), 0.7);
  const double expected = 0.95 / (0.4 * cmax) * e;
  EXPECT_NEAR(flip_mean(Image(24, 24, 0.5f), Image(24, 24, 0.52f)), expected, 1e-4);
}

TEST(Flip, GrowsWithConstantOffset) {
  const Image ref(32, 32, 0.3f);
  double last = 0.0;
  for (float c : {0.005f, 0.01f, 0.02f, 0.05f, 0.1f, 0.2f, 0.4f, 0.7f}) {
    const double f = flip_mean(ref, offset(ref, c));
    EXPECT_GT(f, last) << "offset " << c;
    last = f;
  }
}

TEST(Flip, VisibleNoiseBeatsOffsetAndPixelNoiseIsFiltered) {
  // 67 pixels per degree: a one-pixel checkerboard of +-c lies far above the CSF's pass band and
  // is nearly invisible, less visible than a constant offset c; the same +-c in 8x8 blocks is
  // visible and adds edges, so it scores above the offset.
  const Image ref(64, 64, 0.5f);
  const float c = 0.05f;
  Image checker = ref, blocks = ref;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      checker.at(i, j) += (i + j) % 2 ? c : -c;
      blocks.at(i, j) += (i / 8 + j / 8) % 2 ? c : -c;
    }
  const double f_offset = flip_mean(ref, offset(ref, c));
  const double f_checker = flip_mean(ref, checker);
  const double f_blocks = flip_mean(ref, blocks);
  EXPECT_LT(f_checker, 0.5 * f_offset);
  EXPECT_GT(f_blocks, f_offset);
}

TEST(Flip, ErrorStaysLocal) {
  // A 4x4 change touches only pixels within the CSF radius (10 pixels) of it.
  const Image ref = ramp(64, 64);
  Image est = ref;
  for (int j = 30; j < 34; ++j)
    for (int i = 30; i < 34; ++i) est.at(i, j) = 1.0f;
  const std::vector<float> map = flip_map(ref.view(), est.view(), {});
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const int d = std::max({30 - i, i - 33, 30 - j, j - 33, 0});
      const float v = map[j * 64 + i];
      if (d > 10) {
        EXPECT_EQ(v, 0.0f) << i << "," << j;
      } else if (d == 0) {
        EXPECT_GT(v, 0.5f) << i << "," << j;
      }
      EXPECT_GE(v, 0.0f);
      EXPECT_LE(v, 1.0f);
    }
}

TEST(Flip, EdgeShiftIsLocalised) {
  // A step edge moved by 2 pixels: large error between the two edges, none far from them.
  Image ref(64, 32, 0.2f), est(64, 32, 0.2f);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 64; ++i) {
      if (i >= 32) ref.at(i, j) = 0.8f;
      if (i >= 34) est.at(i, j) = 0.8f;
    }
  const std::vector<float> map = flip_map(ref.view(), est.view(), {});
  EXPECT_GT(map[16 * 64 + 33], 0.5f);
  EXPECT_EQ(map[16 * 64 + 5], 0.0f);
  EXPECT_EQ(map[16 * 64 + 60], 0.0f);
}

TEST(Flip, MatchesAuthorsReferenceCode) {
  // Values printed by the authors' FLIP v1.0 C++ code (research.nvidia.com flip-cpp.zip, run on
  // the sRGB encoding of these grey images at its default 67.02 ppd). It works in float and
  // rounds CIELAB's constants, hence the tolerance.
  const int w = 48, h = 32;
  Image ref(w, h), est(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float a = 0.5f + 0.4f * std::sin(0.3f * i) * std::cos(0.2f * j);
      ref.at(i, j) = a;
      est.at(i, j) = (i >= 20 && i < 28 && j >= 10 && j < 18)
                         ? 0.1f
                         : a + ((i + j) % 2 ? 0.03f : -0.03f) + (i >= 36 ? 0.1f : 0.f);
    }
  const std::vector<float> map = flip_map(ref.view(), est.view(), {});
  EXPECT_NEAR(flip_mean(ref, est), 0.0969327, 2e-5);
  EXPECT_NEAR(map[14 * w + 24], 0.5730021, 1e-4);
  EXPECT_NEAR(map[5 * w + 5], 0.0001509, 1e-5);
  EXPECT_NEAR(map[20 * w + 40], 0.2312281, 1e-4);
}

// Sweeps score many estimates against one reference and reuse FLIP's reference side
// (issue 16): reused, it must give the numbers a fresh scoring gives, bit for bit; prepared for
// another mask, it must not be used.
TEST(Flip, PreparedReferenceSideGivesTheSameBitsAndIsIgnoredForAnotherMask) {
  const int w = 64, h = 48;
  Image ref(w, h), est_a(w, h), est_b(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      ref.at(i, j) = 0.5f + 0.3f * std::sin(0.21f * i + 0.1f * j);
      est_a.at(i, j) = ref.at(i, j) + 0.08f * std::cos(0.5f * i * j);
      est_b.at(i, j) = 0.9f * ref.at(i, j) + 0.04f * ((i + j) % 3);
    }
  std::vector<uint8_t> mask(w * h, 1), other(w * h, 1);
  for (int k = 0; k < w * h; k += 7) mask[k] = 0;
  for (int k = 0; k < w * h; k += 5) other[k] = 0;
  const flip::ReferenceSide side = flip::prepare_reference(w, h, ref.px.data(), mask.data());
  for (const Image* est : {&est_a, &est_b}) {
    const Metrics fresh = compare_images(ref.view(), est->view(), mask, {});
    const Metrics reused = compare_images(ref.view(), est->view(), mask, {}, &side);
    EXPECT_EQ(std::memcmp(&fresh.flip_mean, &reused.flip_mean, sizeof(double)), 0);
    EXPECT_GT(fresh.flip_mean, 0.0);
    const std::vector<float> map = flip::error_map(side, est->px.data());
    const std::vector<float> one_pass =
        flip::error_map(w, h, ref.px.data(), est->px.data(), mask.data());
    EXPECT_EQ(map, one_pass);
  }
  const Metrics right = compare_images(ref.view(), est_a.view(), other, {});
  const Metrics given_wrong_side = compare_images(ref.view(), est_a.view(), other, {}, &side);
  EXPECT_EQ(right.flip_mean, given_wrong_side.flip_mean);
  EXPECT_NE(right.flip_mean, compare_images(ref.view(), est_a.view(), mask, {}).flip_mean);
}

TEST(Flip, MaskOnlyMattersNearItsBoundary) {
  // Pixels farther from every uncompared pixel than the filter radii (10 and 9) see no mask.
  const int w = 80, h = 60;
  Image ref(w, h), est(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      ref.at(i, j) = 0.5f + 0.3f * std::sin(0.21f * i + 0.1f * j);
      est.at(i, j) = ref.at(i, j) + 0.08f * std::cos(0.5f * i * j);
    }
  std::vector<uint8_t> mask(w * h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      if (i < 25 && j < 20) mask[j * w + i] = 0;
  const std::vector<float> full = flip_map(ref.view(), est.view(), {});
  const std::vector<float> part = flip_map(ref.view(), est.view(), mask);
  int checked = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const size_t p = j * w + i;
      if (!mask[p]) {
        EXPECT_EQ(part[p], 0.0f);
      } else if (i >= 25 + 10 || j >= 20 + 10) {
        EXPECT_NEAR(part[p], full[p], 1e-6) << i << "," << j;
        ++checked;
      }
    }
  EXPECT_GT(checked, 2000);
}

TEST(Metrics, SsimMatchesDirectWindowSums) {
  // The separable masked filtering against a direct 11x11 sum, under a random mask.
  const int w = 23, h = 17;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image x(w, h), y(w, h);
  std::vector<uint8_t> mask(w * h);
  for (size_t p = 0; p < mask.size(); ++p)
    x.px[p] = u(rng), y.px[p] = 0.7f * x.px[p] + 0.3f * u(rng), mask[p] = u(rng) < 0.8f;
  const std::vector<float> map = ssim_map(x.view(), y.view(), mask);
  double sum = 0.0;
  int n = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      if (!mask[j * w + i]) continue;
      double s[6] = {0, 0, 0, 0, 0, 0};  // weights, x, y, xx, yy, xy
      for (int dj = -5; dj <= 5; ++dj)
        for (int di = -5; di <= 5; ++di) {
          const int ii = i + di, jj = j + dj;
          if (ii < 0 || jj < 0 || ii >= w || jj >= h || !mask[jj * w + ii]) continue;
          const double g = std::exp(-(di * di + dj * dj) / (2 * 1.5 * 1.5));
          const double a = x.at(ii, jj), b = y.at(ii, jj);
          s[0] += g, s[1] += g * a, s[2] += g * b, s[3] += g * a * a, s[4] += g * b * b,
              s[5] += g * a * b;
        }
      const double mx = s[1] / s[0], my = s[2] / s[0];
      const double vx = s[3] / s[0] - mx * mx, vy = s[4] / s[0] - my * my;
      const double cxy = s[5] / s[0] - mx * my;
      const double c1 = 1e-4, c2 = 9e-4;
      const double expected =
          (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      EXPECT_NEAR(map[j * w + i], expected, 1e-6) << i << "," << j;
      sum += expected;
      ++n;
    }
  EXPECT_NEAR(score(x, y, mask).ssim, sum / n, 1e-6);
}

TEST(Metrics, Deterministic) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image a(97, 61), b(97, 61);
  for (size_t p = 0; p < a.px.size(); ++p) a.px[p] = u(rng), b.px[p] = u(rng);
  const nlohmann::json first = to_json(score(a, b));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(to_json(score(a, b)), first);
}

TEST(Metrics, JsonKeysAndPrefix) {
  const Image ref = ramp(8, 8);
  const nlohmann::json j = to_json(score(ref, offset(ref, 0.125f)), "true_");
  const auto keys = metric_keys();
  ASSERT_EQ(keys.size(), 13u);
  EXPECT_EQ(keys.front(), "pixels");
  EXPECT_EQ(keys.back(), "rmse_excess_sd");
  EXPECT_EQ(j.size(), keys.size());
  for (const auto& k : keys) EXPECT_TRUE(j.contains("true_" + k)) << k;
  EXPECT_TRUE(j.at("true_pixels").is_number_integer());
  EXPECT_NEAR(j.at("true_psnr").get<double>(), -20 * std::log10(0.125), 1e-9);
}

template <class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(Metrics, Errors) {
  const Image a(8, 8, 0.5f), b(8, 6, 0.5f);
  const std::string sizes = error_of([&] { score(a, b); });
  EXPECT_NE(sizes.find("8x8"), std::string::npos) << sizes;
  EXPECT_NE(sizes.find("8x6"), std::string::npos) << sizes;
  EXPECT_EQ(error_of([&] { score(a, a, std::vector<uint8_t>(64, 0)); }),
            "no pixel is covered in both images");
  Image nan_est = a, nan_ref = a;
  nan_est.at(3, 5) = std::numeric_limits<float>::quiet_NaN();
  nan_ref.at(6, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(error_of([&] { score(a, nan_est); }), "NaN in the estimate at pixel (3, 5)");
  EXPECT_EQ(error_of([&] { score(nan_ref, a); }), "NaN in the reference at pixel (6, 1)");
  EXPECT_EQ(error_of([&] { flip_map(nan_ref.view(), a.view(), {}); }),
            "NaN in the reference at pixel (6, 1)");
  EXPECT_EQ(error_of([&] { ssim_map(a.view(), nan_est.view(), {}); }),
            "NaN in the estimate at pixel (3, 5)");
  std::vector<uint8_t> mask(64, 1);
  mask[5 * 8 + 3] = 0;  // the NaN is not compared: fine
  EXPECT_EQ(score(a, nan_est, mask).pixels, 63u);
  EXPECT_NE(error_of([&] { score(a, a, std::vector<uint8_t>(10, 1)); }), "(no InputError)");
  EXPECT_NE(error_of([&] { score(a, a, {}, std::vector<float>(3, 0.0f)); }), "(no InputError)");
}

TEST(Metrics, TimingAt640x480) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image a(640, 480), b(640, 480);
  for (size_t p = 0; p < a.px.size(); ++p) a.px[p] = u(rng), b.px[p] = u(rng);
  const auto t0 = std::chrono::steady_clock::now();
  const Metrics m = score(a, b);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("compare_images 640x480: %.1f ms\n", ms);
  EXPECT_EQ(m.pixels, 640u * 480u);
}

}  // namespace
}  // namespace aoeval
