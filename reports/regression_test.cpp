// Regression rules: the rank test against brute-force enumeration and tabulated values, the
// accuracy noise model against a Monte-Carlo simulation of its own derivation, the verdicts and
// the thresholds file.
#include "reports/regression.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <set>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "base/welch_log_t.h"
#include "harness/results/metric_table.h"
#include "reports/regression_config.h"

namespace aoeval {
namespace {

// P(U >= u_obs) and P(U <= u_obs) by enumerating every assignment of the pooled values to the
// groups and counting pairs directly (no ranks): independent of the implementation.
std::pair<double, double> brute_force(const std::vector<double>& before,
                                      const std::vector<double>& after) {
  std::vector<double> pooled = before;
  pooled.insert(pooled.end(), after.begin(), after.end());
  const int total = static_cast<int>(pooled.size()), n = static_cast<int>(after.size());
  auto u_of = [&](const std::vector<bool>& is_after) {
    double u = 0;
    for (int j = 0; j < total; ++j)
      for (int i = 0; i < total; ++i)
        if (is_after[j] && !is_after[i])
          u += pooled[j] > pooled[i] ? 1.0 : pooled[j] == pooled[i] ? 0.5 : 0.0;
    return u;
  };
  std::vector<bool> observed(total, false);
  for (int j = 0; j < n; ++j) observed[before.size() + j] = true;
  const double u_obs = u_of(observed);
  std::vector<bool> pick(total, false);
  std::fill(pick.end() - n, pick.end(), true);
  double all = 0, ge = 0, le = 0;
  do {
    const double u = u_of(pick);
    all += 1;
    ge += u >= u_obs - 1e-9;
    le += u <= u_obs + 1e-9;
  } while (std::next_permutation(pick.begin(), pick.end()));
  return {ge / all, le / all};
}

TEST(MannWhitney, MatchesBruteForceWithAndWithoutTies) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 30; ++trial) {
    const int m = 2 + trial % 6, n = 2 + (trial / 6) % 5;
    std::uniform_int_distribution<int> coarse(0, trial % 2 ? 4 : 1000);  // odd trials: many ties
    std::vector<double> before(m), after(n);
    for (auto& v : before) v = coarse(rng);
    for (auto& v : after) v = coarse(rng) + (trial % 3);
    const RankTest t = mann_whitney(before, after);
    const auto [ge, le] = brute_force(before, after);
    EXPECT_TRUE(t.exact);
    EXPECT_NEAR(t.p_greater, ge, 1e-12) << "trial " << trial;
    EXPECT_NEAR(t.p_less, le, 1e-12) << "trial " << trial;
  }
}

TEST(MannWhitney, TabulatedValuesForFiveAgainstFive) {
  // The null distribution of U for m = n = 5 has counts 1, 1, 2, 3, 5, 7, ... out of C(10,5) = 252.
  const std::vector<double> before = {3, 4, 5, 6, 7};
  const RankTest separated = mann_whitney(before, {8, 9, 10, 11, 12});
  EXPECT_EQ(separated.u, 25.0);
  EXPECT_NEAR(separated.p_greater, 1.0 / 252, 1e-15);
  EXPECT_NEAR(separated.p_two_sided, 2.0 / 252, 1e-15);
  const RankTest three = mann_whitney(before, {0.5, 1, 1.5, 3.5, 4.5});  // pairs: 3.5>3, 4.5>3,4
  EXPECT_EQ(three.u, 3.0);
  EXPECT_NEAR(three.p_less, 7.0 / 252, 1e-15);
  const RankTest identical = mann_whitney(before, before);  // U = mn/2, the centre
  EXPECT_EQ(identical.u, 12.5);
  EXPECT_GT(identical.p_greater, 0.5);
  EXPECT_EQ(identical.p_two_sided, 1.0);
  EXPECT_EQ(smallest_one_sided_p(5, 5), 1.0 / 252);
  EXPECT_NEAR(smallest_one_sided_p(3, 3), 1.0 / 20, 1e-15);
}

// Welch's t on log times against scipy.stats.ttest_ind(log a, log b, equal_var=False) (SciPy
// 1.10): t, the Welch-Satterthwaite df and the one-sided p-values.
TEST(WelchLogT, MatchesScipy) {
  const LogTTest twice = welch_log_t_test({10, 10.1, 9.9}, {20, 20.1, 19.9});
  EXPECT_NEAR(twice.t, 107.38234967941578, 1e-9);
  EXPECT_NEAR(twice.p_greater, 1.111695388568314e-06, 1e-15);
  const LogTTest mixed = welch_log_t_test({10, 10.3, 9.7}, {10.4, 10.6, 10.2, 10.5, 10.9});
  EXPECT_NEAR(mixed.t, 2.475012780277218, 1e-12);
  EXPECT_NEAR(mixed.df, 3.6322491998002135, 1e-12);
  EXPECT_NEAR(mixed.p_greater, 0.037472639334881104, 1e-12);
  EXPECT_NEAR(mixed.p_less, 0.9625273606651189, 1e-12);
  const LogTTest flat = welch_log_t_test({5, 5}, {6, 6, 6});  // no spread: the difference is known
  EXPECT_LT(flat.p_greater, 1e-12);  // 0 up to the rounding of the mean of three equal logs
  EXPECT_GT(flat.p_less, 1.0 - 1e-12);
  const LogTTest exact = welch_log_t_test({5, 5}, {6, 6});  // means of two: exact, no spread
  EXPECT_EQ(exact.p_greater, 0.0);
  EXPECT_EQ(exact.p_less, 1.0);
  EXPECT_THROW(welch_log_t_test({5}, {6, 6}), std::invalid_argument);
  EXPECT_THROW(welch_log_t_test({5, 0}, {6, 6}), std::invalid_argument);
}

TEST(MannWhitney, NormalApproximationIsCloseToExactForTwentyAgainstTwenty) {
  // At m = n = 20 the continuity-corrected normal approximation is within a few thousandths of
  // the exact tail near p = 0.05 (Mann & Whitney 1947 recommend it above m, n ~ 8).
  std::vector<double> before, after;
  for (int i = 0; i < 20; ++i) {
    before.push_back(i);
    after.push_back(i + 3.5);  // U = 264 of 400 (mean 200, sd 37): p(greater) about 0.04
  }
  const RankTest exact = mann_whitney(before, after, 60);
  const RankTest normal = mann_whitney(before, after, 0);
  EXPECT_TRUE(exact.exact);
  EXPECT_FALSE(normal.exact);
  EXPECT_EQ(exact.u, normal.u);
  EXPECT_GT(exact.p_greater, 0.005);
  EXPECT_LT(exact.p_greater, 0.2);
  EXPECT_NEAR(normal.p_greater, exact.p_greater, 0.005);
  // All values tied: no evidence either way.
  const RankTest tied = mann_whitney(std::vector<double>(40, 1.0), std::vector<double>(40, 1.0));
  EXPECT_FALSE(tied.exact);
  EXPECT_EQ(tied.p_greater, 1.0);
  EXPECT_THROW(mann_whitney({}, {1.0}), std::invalid_argument);
}

// The derivation in regression.cpp, simulated: N pixels with a fixed estimate error d_i and a
// reference noise n_i ~ N(0, s^2); rmse_excess computed exactly as CONTRACT §4 defines it.
struct Simulation {
  int pixels = 4000;
  double s = 0.02;  // reference stderr per pixel
  std::mt19937_64 rng{11};
  std::vector<double> errors(double rms) {  // a fixed error pattern with the given rms
    std::vector<double> d(pixels);
    for (int i = 0; i < pixels; ++i) d[i] = rms * std::sqrt(2.0) * std::sin(0.37 * i + 0.1);
    return d;
  }
  static double rmse_excess(const std::vector<double>& d, const std::vector<double>& noise,
                            double s) {
    double sum = 0;
    for (size_t i = 0; i < d.size(); ++i) sum += (d[i] - noise[i]) * (d[i] - noise[i]);
    return std::sqrt(std::max(0.0, sum / d.size() - s * s));
  }
  std::vector<double> noise() {
    std::normal_distribution<double> g(0.0, s);
    std::vector<double> n(pixels);
    for (auto& v : n) v = g(rng);
    return n;
  }
};

double stddev(const std::vector<double>& v) {
  double mean = 0, sq = 0;
  for (double x : v) mean += x;
  mean /= v.size();
  for (double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / (v.size() - 1));
}

TEST(AccuracyNoise, IndependentReferencesMatchSimulation) {
  // 1500 trials: the sample standard deviation is within 2.2% (1/sqrt(2*1500) relative) of the
  // truth, so 8% is about four standard errors; the model's own approximations (Gaussian noise,
  // delta method) are far smaller at D = 3 s and N = 4000.
  Simulation sim;
  const auto d = sim.errors(3 * sim.s);
  std::vector<double> single, change, bias_change;
  for (int t = 0; t < 1500; ++t) {
    const auto n1 = sim.noise(), n2 = sim.noise();
    const double a = Simulation::rmse_excess(d, n1, sim.s),
                 b = Simulation::rmse_excess(d, n2, sim.s);
    single.push_back(a);
    change.push_back(a - b);
    double m1 = 0, m2 = 0;
    for (int i = 0; i < sim.pixels; ++i) {
      m1 += d[i] - n1[i];
      m2 += d[i] - n2[i];
    }
    bias_change.push_back((m1 - m2) / sim.pixels);
  }
  AccuracySample sample{3 * sim.s, sim.s, 0.0, static_cast<double>(sim.pixels)};
  EXPECT_NEAR(stddev(single) / rmse_excess_sigma(sample), 1.0, 0.08);
  const AccuracyNoise noise = accuracy_noise(sample, sample, false, std::nullopt);
  EXPECT_NEAR(stddev(change) / noise.rmse_excess_sigma, 1.0, 0.08);
  EXPECT_NEAR(stddev(bias_change) / noise.bias_sigma, 1.0, 0.08);
}

TEST(AccuracyNoise, SameReferenceCancelsButForTheCrossTerm) {
  // Same noise draw on both sides; the estimate changes by a pattern of rms delta. The change of
  // rmse_excess varies across draws with sigma 2 s delta / (sqrt(N) (D_a + D_b)).
  Simulation sim;
  const auto d = sim.errors(3 * sim.s);
  std::vector<double> d2(d.size());
  const double delta = 0.5 * sim.s;
  for (size_t i = 0; i < d.size(); ++i) d2[i] = d[i] + delta * std::sqrt(2.0) * std::cos(0.11 * i);
  double D2 = 0;
  for (double v : d2) D2 += v * v;
  D2 = std::sqrt(D2 / d2.size());
  std::vector<double> change;
  for (int t = 0; t < 1500; ++t) {
    const auto n = sim.noise();
    change.push_back(Simulation::rmse_excess(d2, n, sim.s) - Simulation::rmse_excess(d, n, sim.s));
  }
  const AccuracySample b{3 * sim.s, sim.s, 0.0, static_cast<double>(sim.pixels)};
  const AccuracySample a{D2, sim.s, 0.0, static_cast<double>(sim.pixels)};
  const AccuracyNoise noise = accuracy_noise(b, a, true, delta);
  EXPECT_NEAR(stddev(change) / noise.rmse_excess_sigma, 1.0, 0.08);
  EXPECT_EQ(noise.bias_sigma, 0.0);
  // Without the images the independent-reference sigma stands in (larger here).
  EXPECT_GT(accuracy_noise(b, a, true, std::nullopt).rmse_excess_sigma, noise.rmse_excess_sigma);
  // An unchanged deterministic estimate: no noise at all.
  EXPECT_EQ(accuracy_noise(b, b, true, 0.0).rmse_excess_sigma, 0.0);
}

ResultRow row(double rmse_excess, double bias, std::vector<double> times) {
  ResultRow r;
  r.run_name = "e/scene:s/view:v/8x8";
  r.estimator = "e";
  r.scene = "s";
  r.view = "v";
  r.width = r.height = 8;
  r.device = "cpu";
  r.reference = {{"spp", 64}};
  r.metrics = {
      {"rmse_excess", rmse_excess}, {"ref_stderr_rms", 0.01}, {"bias", bias}, {"pixels", 10000}};
  r.time_ms_samples = times;
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  r.time_ms_median = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
  return r;
}

const Check& check(const std::vector<Check>& checks, const std::string& figure) {
  for (const auto& c : checks)
    if (c.figure == figure) return c;
  throw std::runtime_error("no check " + figure);
}

const std::vector<double> kTimes = {10.0, 10.2, 9.9, 10.1, 10.05};

// The mean and the sample standard deviation of simulated draws.
struct Spread {
  double mean = 0.0, sd = 0.0;
};
Spread spread_of(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  Spread s;
  for (double v : values) s.mean += v / n;
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean) / (n - 1.0);
  s.sd = std::sqrt(var);
  return s;
}

TEST(CompareRows, AccuracyBelowThresholdPassesAndClearRegressionFails) {
  const Thresholds t;
  // Same reference, unchanged estimate: identical numbers.
  const auto same = compare_rows(row(0.05, 0.01, kTimes), row(0.05, 0.01, kTimes), t, 0.0);
  EXPECT_EQ(worst(same), Verdict::unchanged);
  // A 3% rise: under the 5% relative threshold even though noise-free.
  EXPECT_EQ(check(compare_rows(row(0.05, 0.01, kTimes), row(0.0515, 0.01, kTimes), t, 0.002),
                  "rmse_excess")
                .verdict,
            Verdict::unchanged);
  // A 40% rise: regressed.
  const auto worse = compare_rows(row(0.05, 0.01, kTimes), row(0.07, 0.01, kTimes), t, 0.02);
  EXPECT_EQ(check(worse, "rmse_excess").verdict, Verdict::regressed);
  EXPECT_EQ(worst(worse), Verdict::regressed);
  // The same fall: improved.
  EXPECT_EQ(
      check(compare_rows(row(0.07, 0.01, kTimes), row(0.05, 0.01, kTimes), t, 0.02), "rmse_excess")
          .verdict,
      Verdict::improved);
  // |bias| 0.01 -> 0.03: regressed; -0.01 -> 0.01: the same magnitude, unchanged.
  EXPECT_EQ(check(compare_rows(row(0.05, 0.01, kTimes), row(0.05, 0.03, kTimes), t, 0.02), "|bias|")
                .verdict,
            Verdict::regressed);
  EXPECT_EQ(
      check(compare_rows(row(0.05, -0.01, kTimes), row(0.05, 0.01, kTimes), t, 0.02), "|bias|")
          .verdict,
      Verdict::unchanged);
}

// The dashboard judges exactly the metrics the metric table marks as judged (|bias| for bias).
TEST(CompareRows, ChecksTheMetricTablesDashboardKeys) {
  ResultRow r = row(0.05, 0.01, kTimes);
  r.metrics["bent_angle_excess"] = 2.0;
  r.metrics["bent_ref_stderr"] = 0.5;
  r.metrics["bent_pixels"] = 100;
  for (const std::string& key : metric_keys_of(MetricFamily::sequence)) r.metrics[key] = 1.0;
  std::set<std::string> judged;
  for (const Check& c : compare_rows(r, r, Thresholds{}, 0.0))
    if (c.figure != "time_ms_median" && c.figure != "status")
      judged.insert(c.figure == "|bias|" ? "bias" : c.figure);
  const auto keys = dashboard_metric_keys();
  EXPECT_EQ(judged, std::set<std::string>(keys.begin(), keys.end()));
}

// The sequence keys (CONTRACT §10) are judged with their own rules where both rows carry them;
// a still row (no sequence keys) and a key one side lacks are not judged.
TEST(CompareRows, SequenceKeysAreJudgedWhereBothRowsCarryThem) {
  const Thresholds t;
  auto judged = [](const std::vector<Check>& checks, const std::string& figure) {
    return std::any_of(checks.begin(), checks.end(),
                       [&](const Check& c) { return c.figure == figure; });
  };
  const ResultRow still = row(0.05, 0.01, kTimes);
  EXPECT_FALSE(judged(compare_rows(still, still, t, 0.0), "temporal_rmse_excess"));
  ResultRow before = still, after = still;
  for (ResultRow* r : {&before, &after})
    r->metrics.update({{"seq_frames", 16},
                       {"seq_rmse_excess", 0.03},
                       {"steady_rmse_excess", 0.025},
                       {"temporal_rmse_excess", 0.0129},
                       {"converge_frames", 4},
                       {"disocclusion_rmse_excess", 0.06}});
  EXPECT_EQ(worst(compare_rows(before, after, t, 0.0)), Verdict::unchanged);
  after.metrics["temporal_rmse_excess"] = 0.0411;  // 3.2x the flicker
  const auto checks = compare_rows(before, after, t, 0.0);
  for (const Check& c : checks)
    EXPECT_EQ(c.verdict == Verdict::regressed, c.figure == "temporal_rmse_excess") << c.figure;
  // converge_frames: 4 -> 6 is within max(25 %, 2 frames); 4 -> 7 is not.
  after = before;
  after.metrics["converge_frames"] = 6;
  EXPECT_EQ(check(compare_rows(before, after, t, 0.0), "converge_frames").verdict,
            Verdict::unchanged);
  after.metrics["converge_frames"] = 7;
  EXPECT_EQ(check(compare_rows(before, after, t, 0.0), "converge_frames").verdict,
            Verdict::regressed);
  // A key one row lacks (an older run's column): not judged, not an error.
  after.metrics.erase("disocclusion_rmse_excess");
  EXPECT_FALSE(judged(compare_rows(before, after, t, 0.0), "disocclusion_rmse_excess"));
  // Thresholds from the config like any other key.
  const RegressionConfig c = RegressionConfig::parse(
      {{"defaults", {{"converge_frames_absolute", 4}, {"temporal_rmse_excess_relative", 0.5}}}},
      "t.json");
  EXPECT_EQ(c.thresholds("e", "s").rule("converge_frames").absolute, 4.0);
  EXPECT_EQ(c.thresholds("e", "s").rule("temporal_rmse_excess").relative, 0.5);
  EXPECT_EQ(c.thresholds("e", "s").rule("temporal_rmse_excess").absolute, 2e-4);
  EXPECT_EQ(
      check(compare_rows(before, after, c.thresholds("e", "s"), 0.0), "converge_frames").verdict,
      Verdict::unchanged);
  EXPECT_THROW(RegressionConfig::parse({{"defaults", {{"seq_frames_relative", 1}}}}, "t.json"),
               InputError);  // seq_frames is a length, not judged
}

// seq_rmse_excess pools F frames of N pixels, each frame against its own reference: its spread
// over 1500 draws matches metric_noise_sigma (rmse_excess_sigma with N F pixels) within four
// standard errors of a standard deviation (8 %).
TEST(AccuracyNoise, SequenceSigmaMatchesSimulation) {
  const int pixels = 500, frames = 8, draws = 1500;
  const double s = 0.02;
  std::mt19937_64 rng{11};
  std::normal_distribution<double> noise(0.0, s);
  std::vector<double> d(static_cast<size_t>(pixels) * frames);
  for (size_t i = 0; i < d.size(); ++i) d[i] = 0.03 * std::sin(0.37 * static_cast<double>(i));
  std::vector<double> values;
  for (int k = 0; k < draws; ++k) {
    double sum = 0.0;
    for (int f = 0; f < frames; ++f) {
      double sq = 0.0;
      for (int i = 0; i < pixels; ++i) {
        const double e = d[static_cast<size_t>(f) * pixels + i] - noise(rng);
        sq += e * e;
      }
      sum += std::max(0.0, sq / pixels - s * s);  // one frame's rmse_excess^2
    }
    values.push_back(std::sqrt(sum / frames));
  }
  const Spread drawn = spread_of(values);
  ResultRow r = row(0.0, 0.0, kTimes);
  r.metrics = {
      {"rmse_excess", drawn.mean}, {"ref_stderr_rms", s},           {"bias", 0.0},
      {"pixels", pixels},          {"seq_rmse_excess", drawn.mean}, {"seq_frames", frames}};
  const double sigma = metric_noise_sigma("seq_rmse_excess", r);
  EXPECT_NEAR(drawn.sd, sigma, 4.0 * sigma / std::sqrt(2.0 * draws)) << "mean " << drawn.mean;
}

// A static camera over a static scene: the F frames share one reference (traced once, issue 42),
// so its noise is the same in every frame and pooling frames does not average it away. With an
// estimate that repeats itself (constant, a deterministic estimator on a still view) the spread of
// seq_rmse_excess over 1500 draws of that one reference matches metric_noise_sigma with
// seq_reference_frames = 1 (N pixels; N F would make it sqrt(8) too small), within four standard
// errors of a standard deviation (8 %).
TEST(AccuracyNoise, SharedReferenceSigmaMatchesSimulation) {
  const int pixels = 500, frames = 8, draws = 1500;
  const double s = 0.02;
  std::mt19937_64 rng{12};
  std::normal_distribution<double> noise(0.0, s);
  std::vector<double> d(pixels);
  for (int i = 0; i < pixels; ++i) d[i] = 0.03 * std::sin(0.37 * i);
  std::vector<double> values, ref(pixels);
  for (int k = 0; k < draws; ++k) {
    for (double& r : ref) r = noise(rng);  // the one reference of every frame
    double sum = 0.0;
    for (int f = 0; f < frames; ++f) {
      double sq = 0.0;
      for (int i = 0; i < pixels; ++i) {
        const double e = d[i] - ref[i];
        sq += e * e;
      }
      sum += std::max(0.0, sq / pixels - s * s);
    }
    values.push_back(std::sqrt(sum / frames));
  }
  const Spread drawn = spread_of(values);
  ResultRow r = row(0.0, 0.0, kTimes);
  r.metrics = {{"rmse_excess", drawn.mean}, {"ref_stderr_rms", s},           {"bias", 0.0},
               {"pixels", pixels},          {"seq_rmse_excess", drawn.mean}, {"seq_frames", frames},
               {"seq_reference_frames", 1}};
  const double sigma = metric_noise_sigma("seq_rmse_excess", r);
  EXPECT_NEAR(drawn.sd, sigma, 4.0 * sigma / std::sqrt(2.0 * draws)) << "mean " << drawn.mean;
  // Without the key (a row from before it) the frames count as independent references.
  r.metrics.erase("seq_reference_frames");
  EXPECT_NEAR(metric_noise_sigma("seq_rmse_excess", r) * std::sqrt(frames), sigma, 1e-3 * sigma);
  // One reference for every frame: frame differences hold none of its noise.
  r.metrics["seq_reference_frames"] = 1;
  r.metrics["temporal_rmse_excess"] = 0.01;
  EXPECT_EQ(metric_noise_sigma("temporal_rmse_excess", r), 0.0);
}

TEST(CompareRows, NoiseWidensTheThreshold) {
  // Independent references (different spp), s = 0.01 over only N = 100 pixels:
  // sigma(D) = s sqrt(D^2 + s^2/2) / (D sqrt(N)) = 0.00106 at D = 0.02 and 0.00104 at D = 0.024,
  // so the change has sigma 0.00149 and 3 sigma = 0.00446 exceeds 5% of 0.02 (0.001): a 0.004 rise
  // is noise, a 0.02 rise is not.
  ResultRow before = row(0.02, 0.0, kTimes), after = row(0.024, 0.0, kTimes);
  before.metrics["pixels"] = after.metrics["pixels"] = 100;
  after.reference = {{"spp", 256}};
  const Thresholds t;
  const Check small = check(compare_rows(before, after, t, std::nullopt), "rmse_excess");
  EXPECT_EQ(small.verdict, Verdict::unchanged) << small.detail;
  EXPECT_NEAR(small.threshold, 0.00446, 0.00001);
  after.metrics["rmse_excess"] = 0.04;
  EXPECT_EQ(check(compare_rows(before, after, t, std::nullopt), "rmse_excess").verdict,
            Verdict::regressed);
}

TEST(CompareRows, TimingNeedsARankTestAndTheRelativeThreshold) {
  const Thresholds t;
  auto scaled = [](double f) {
    std::vector<double> v = kTimes;
    for (auto& x : v) x *= f;
    return v;
  };
  // The same distribution (a permutation of it): unchanged.
  EXPECT_EQ(check(compare_rows(row(0.05, 0, kTimes), row(0.05, 0, {10.1, 9.9, 10.05, 10.2, 10.0}),
                               t, 0.0),
                  "time_ms_median")
                .verdict,
            Verdict::unchanged);
  // 30% slower, every repetition: regressed (p = 1/252 < 0.01, x1.3 > x1.1).
  const Check slower = check(compare_rows(row(0.05, 0, kTimes), row(0.05, 0, scaled(1.3)), t, 0.0),
                             "time_ms_median");
  EXPECT_EQ(slower.verdict, Verdict::regressed) << slower.detail;
  // 5% slower, every repetition: significant but under the 10% threshold.
  EXPECT_EQ(check(compare_rows(row(0.05, 0, kTimes), row(0.05, 0, scaled(1.05)), t, 0.0),
                  "time_ms_median")
                .verdict,
            Verdict::unchanged);
  // 30% slower median but overlapping samples (one fast outlier each way): not significant.
  EXPECT_EQ(check(compare_rows(row(0.05, 0, {10, 13, 9, 14, 10.5}),
                               row(0.05, 0, {13, 10, 14, 13.5, 9.5}), t, 0.0),
                  "time_ms_median")
                .verdict,
            Verdict::unchanged);
  // 30% faster: improved.
  EXPECT_EQ(
      check(compare_rows(row(0.05, 0, kTimes), row(0.05, 0, scaled(0.7)), t, 0.0), "time_ms_median")
          .verdict,
      Verdict::improved);
  // Three repetitions cannot reach p < 0.01 with the rank test (1/20 at best): Welch's t on the
  // log times judges, and the detail says so. Twice as slow, each side within 1 %: regressed.
  const Check few =
      check(compare_rows(row(0.05, 0, {10, 10.1, 9.9}), row(0.05, 0, {20, 20.1, 19.9}), t, 0.0),
            "time_ms_median");
  EXPECT_EQ(few.verdict, Verdict::regressed) << few.detail;
  EXPECT_NE(few.detail.find("Welch"), std::string::npos);
  // 5 % slower (3 against 5 repetitions, p(slower) 0.037): under alpha's bar and the ratio's.
  EXPECT_EQ(check(compare_rows(row(0.05, 0, {10, 10.3, 9.7}),
                               row(0.05, 0, {10.4, 10.6, 10.2, 10.5, 10.9}), t, 0.0),
                  "time_ms_median")
                .verdict,
            Verdict::unchanged);
  // 40 % slower but spread over +-30 % on one side: p(slower) above 0.01, unchanged.
  EXPECT_EQ(check(compare_rows(row(0.05, 0, {10, 13, 7}), row(0.05, 0, {14, 14.1, 13.9}), t, 0.0),
                  "time_ms_median")
                .verdict,
            Verdict::unchanged);
  // One repetition a side: no test can judge; not compared, and the page says why.
  const Check single =
      check(compare_rows(row(0.05, 0, {10}), row(0.05, 0, {20}), t, 0.0), "time_ms_median");
  EXPECT_EQ(single.verdict, Verdict::not_compared);
  EXPECT_NE(single.detail.find("too few repetitions"), std::string::npos);
  // A time of 0 (a clock too coarse) has no logarithm: not compared, and the detail says that.
  const Check zero = check(compare_rows(row(0.05, 0, {0, 0, 0}), row(0.05, 0, {1, 1, 1}), t, 0.0),
                           "time_ms_median");
  EXPECT_EQ(zero.verdict, Verdict::not_compared);
  EXPECT_NE(zero.detail.find("not positive"), std::string::npos) << zero.detail;
  // Another device: not compared.
  ResultRow gpu = row(0.05, 0, scaled(2.0));
  gpu.device = "gpu";
  EXPECT_EQ(check(compare_rows(row(0.05, 0, kTimes), gpu, t, 0.0), "time_ms_median").verdict,
            Verdict::not_compared);
}

TEST(CompareRows, MissingRowsFollowTheConfig) {
  Thresholds t;
  ResultRow skipped = row(0.05, 0, kTimes);
  skipped.status = "skipped: no Vulkan device";
  EXPECT_EQ(missing_check(&skipped, t).verdict, Verdict::regressed);
  EXPECT_NE(missing_check(&skipped, t).detail.find("no Vulkan device"), std::string::npos);
  t.missing_fails = false;
  EXPECT_EQ(missing_check(nullptr, t).verdict, Verdict::warning);
}

TEST(RegressionConfig, OverridesApplyInOrderAndUnknownKeysAreErrors) {
  const nlohmann::json j = {
      {"defaults", {{"time_relative", 0.2}, {"rmse_excess_sigmas", 4}}},
      {"scenes", {{"bunny", {{"time_relative", 0.3}, {"bias_absolute", 0.01}}}}},
      {"estimators", {{"hbao", {{"time_relative", 0.5}, {"missing", "warn"}}}}},
      {"comment", "test"}};
  const RegressionConfig c = RegressionConfig::parse(j, "t.json");
  EXPECT_EQ(c.thresholds("x", "y").time_relative, 0.2);
  EXPECT_EQ(c.thresholds("x", "y").rmse_excess_sigmas, 4.0);
  EXPECT_EQ(c.thresholds("x", "y").rmse_excess_relative, Thresholds{}.rmse_excess_relative);
  EXPECT_EQ(c.thresholds("x", "bunny").time_relative, 0.3);
  EXPECT_EQ(c.thresholds("hbao", "bunny").time_relative, 0.5);   // estimator beats scene
  EXPECT_EQ(c.thresholds("hbao", "bunny").bias_absolute, 0.01);  // scene still applies
  EXPECT_FALSE(c.thresholds("hbao", "y").missing_fails);
  EXPECT_TRUE(c.thresholds("x", "y").missing_fails);

  auto error_of = [](const nlohmann::json& bad) {
    try {
      RegressionConfig::parse(bad, "t.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of({{"defaults", {{"time_relativ", 0.2}}}}).find("time_relativ"),
            std::string::npos);
  EXPECT_NE(error_of({{"scenes", {{"bunny", {{"sigma", 1}}}}}}).find("scenes.bunny.sigma"),
            std::string::npos);
  EXPECT_NE(error_of({{"default", {}}}).find("default"), std::string::npos);
  EXPECT_NE(error_of({{"defaults", {{"time_alpha", 1.5}}}}).find("time_alpha"), std::string::npos);
  EXPECT_NE(error_of({{"defaults", {{"missing", "maybe"}}}}).find("missing"), std::string::npos);
  EXPECT_NE(error_of({{"defaults", {{"bias_sigmas", -1}}}}).find("bias_sigmas"), std::string::npos);
  EXPECT_NE(error_of({{"defaults", {{"change_action", "stop"}}}}).find("change_action"),
            std::string::npos);
}

TEST(RegressionConfig, ChangeKeysTakeDefaultsAndOverrides) {
  EXPECT_EQ(Thresholds{}.change_mean_shift, 0.005);
  EXPECT_FALSE(Thresholds{}.change_fails);
  const RegressionConfig c = RegressionConfig::parse(
      {{"defaults", {{"change_mean_shift", 0.01}, {"change_action", "fail"}}},
       {"scenes", {{"tree-apple", {{"change_mean_shift", 0.02}}}}},
       {"estimators", {{"shadowmap-ao", {{"change_action", "warn"}}}}}},
      "t.json");
  EXPECT_EQ(c.thresholds("x", "bunny").change_mean_shift, 0.01);
  EXPECT_TRUE(c.thresholds("x", "bunny").change_fails);
  EXPECT_EQ(c.thresholds("x", "tree-apple").change_mean_shift, 0.02);
  EXPECT_FALSE(c.thresholds("shadowmap-ao", "tree-apple").change_fails);
}

TEST(RegressionConfig, TheShippedFileLoads) {
  const RegressionConfig c = RegressionConfig::load(default_regression_config_path());
  EXPECT_EQ(c.source(), default_regression_config_path());
  EXPECT_THROW(RegressionConfig::load("/nonexistent/dashboard.json"), InputError);
}

// A thresholds file that is not JSON (NaN) or holds a number no double holds (1e400) is one line
// naming the file and the key, not nlohmann's "[json.exception...]" text.
TEST(RegressionConfig, InvalidValuesNameTheFileAndKey) {
  const std::string path = (testutil::test_temp_dir("regression_config") / "t.json").string();
  for (const auto& [value, expected] : std::vector<std::pair<std::string, std::string>>{
           {"NaN", path + ":1:39: invalid JSON (at key defaults.rmse_excess_relative)"},
           {"1e400", path + ": invalid JSON at key defaults.rmse_excess_relative: number overflow "
                            "parsing '1e400'"}}) {
    std::ofstream(path) << "{\"defaults\": {\"rmse_excess_relative\": " << value << "}}";
    try {
      RegressionConfig::load(path);
      ADD_FAILURE() << value << " loaded";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
}

// Bent normals (regression.cpp): a fixed 2-D angular error pattern of rms D and the reference's
// Gaussian 2-D noise of total variance s^2 per pixel; the spread of bent_angle_excess over
// 1500 draws matches bent_excess_sigma within four standard errors of a standard deviation (8 %).
TEST(AccuracyNoise, BentExcessSigmaMatchesSimulation) {
  const int pixels = 4000;
  const double s = 2.0, d = 6.0;  // degrees
  std::mt19937_64 rng{5};
  std::normal_distribution<double> g(0.0, s / std::sqrt(2.0));  // per axis
  std::vector<double> excess;
  for (int t = 0; t < 1500; ++t) {
    double sum = 0.0;
    for (int i = 0; i < pixels; ++i) {
      const double ex = d * std::cos(0.37 * i), ey = d * std::sin(0.37 * i);  // |e| = D
      const double x = ex - g(rng), y = ey - g(rng);
      sum += x * x + y * y;
    }
    excess.push_back(std::sqrt(std::max(0.0, sum / pixels - s * s)));
  }
  EXPECT_NEAR(stddev(excess) / bent_excess_sigma(d, s, pixels), 1.0, 0.08);
  EXPECT_EQ(bent_excess_sigma(d, 0.0, pixels), 0.0);
}

TEST(CompareRows, BentNormalsAreTrackedWhereRowsCarryThem) {
  const Thresholds t;
  ResultRow before = row(0.05, 0.01, kTimes), after = row(0.05, 0.01, kTimes);
  EXPECT_THROW(check(compare_rows(before, after, t, 0.0), "bent_angle_excess"),
               std::runtime_error);  // no bent metrics: no check
  for (ResultRow* r : {&before, &after}) {
    r->metrics["bent_angle_excess"] = 5.0;
    r->metrics["bent_ref_stderr"] = 2.0;
    r->metrics["bent_pixels"] = 10000;
  }
  EXPECT_EQ(check(compare_rows(before, after, t, 0.0), "bent_angle_excess").verdict,
            Verdict::unchanged);
  after.metrics["bent_angle_excess"] = 7.0;  // +40 %, far beyond 3 sigma (~0.06 degrees)
  EXPECT_EQ(check(compare_rows(before, after, t, 0.0), "bent_angle_excess").verdict,
            Verdict::regressed);
  after.metrics["bent_angle_excess"] = 5.1;  // +2 %: under the 5 % threshold
  EXPECT_EQ(check(compare_rows(before, after, t, 0.0), "bent_angle_excess").verdict,
            Verdict::unchanged);
}

}  // namespace
}  // namespace aoeval
