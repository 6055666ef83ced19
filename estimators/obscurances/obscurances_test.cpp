// Ray-traced obscurances (Méndez et al. 2003) against the Embree reference and closed forms. Every
// statistical check pools many independent pixels (each pixel draws from its own stream) and
// allows 4 standard errors of the pooled mean (a false alarm about once in 16,000 runs); the
// standard errors come from the spread of the pixels themselves, never from trial and error.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "base/errors.h"
#include "estimators/obscurances/obscurances.h"
#include "estimators/registry.h"
#include "references/reference.h"
#include "scenes/analytic_scenes.h"
#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

// Mean and standard error of the mean of i.i.d. values (the probe's pixels).
struct Pooled {
  double mean, stderr_of_mean, variance;
};
template <class F>
Pooled pooled(size_t n, F value) {
  double sum = 0.0, sum_sq = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const double v = value(k);
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / n, var = std::max(0.0, (sum_sq - sum * mean) / (n - 1.0));
  return {mean, std::sqrt(var / n), var};
}

ObscuranceSettings settings(Falloff rho, SamplerKind sampling, double dmax, int rays = 16) {
  ObscuranceSettings s = obscurance_settings_of(default_params(obscurances_estimator()));
  s.rho = rho;
  s.sampling = sampling;
  s.dmax = dmax;
  s.rays = rays;
  return s;
}

const Falloff kRhos[] = {Falloff::none, Falloff::sqrt, Falloff::exp, Falloff::power(3.0)};
const SamplerKind kSamplings[] = {SamplerKind::random, SamplerKind::stratified};

// A floor, a sphere and a box, seen from above: occluders at every distance.
class SmallScene : public ::testing::Test {
 protected:
  SmallScene()
      : scene_(scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                         generated("ball", "sphere", {{"radius", 0.5}}, {0.0f, 0.5f, 0.0f}),
                         generated("block", "box", nlohmann::json::object(), {1.1f, 0.0f, -0.4f},
                                   {0.9f, 0.2f, 0.1f})})),
        es_(scene_) {
    View v;
    v.eye = {0.2f, 1.6f, 2.6f};
    v.target = {0.4f, 0.3f, 0.0f};
    g_ = render_gbuffer(es_, make_camera(v, 64, 48));
  }
  ReferenceSettings reference_settings(Falloff rho, double dmax, int spp, uint64_t seed) const {
    ReferenceSettings r;
    r.sampler = SamplerKind::random;
    r.spp = spp;
    r.seed = seed;
    r.definition.dmax = dmax;
    r.definition.falloff = rho;
    return r;
  }
  Scene scene_;
  EmbreeScene es_;
  GBuffer g_;
};

TEST_F(SmallScene, RandomSamplingIsTheReferenceBitForBit) {
  // Same seed, same directions, origins and ray values: eq. 2 with rho = the falloff of CONTRACT
  // §3 is exactly what the reference computes (compute_reference, random sampler, spp = rays).
  for (auto rho : kRhos) {
    ObscuranceSettings s = settings(rho, SamplerKind::random, 0.6, 24);
    s.seed = 5;
    const ObscuranceImage o = compute_obscurances(es_, g_, s, average_reflectivity(scene_));
    const ReferenceImage r = compute_reference(es_, g_, reference_settings(rho, 0.6, 24, 5));
    EXPECT_EQ(o.grey, r.ao) << falloff_name(rho);
  }
}

TEST_F(SmallScene, EveryRhoMatchesTheReferenceOfItsFalloffWithinNoise) {
  // The pooled mean over covered pixels of (estimate - reference). Its variance is the sum of the
  // pixels' variances over N^2: the reference's from its stderr, the estimator's (systematic
  // sampling has no honest per-pixel variance) from two independent seeds: Var(e1 - e2) = 2 Var(e).
  for (auto rho : kRhos)
    for (auto sampling : kSamplings) {
      ObscuranceSettings s = settings(rho, sampling, 0.6);
      const ObscuranceImage e1 = compute_obscurances(es_, g_, s, glm::vec3(0.7f));
      s.seed = 8;
      const ObscuranceImage e2 = compute_obscurances(es_, g_, s, glm::vec3(0.7f));
      const ReferenceImage r = compute_reference(es_, g_, reference_settings(rho, 0.6, 256, 1));
      double diff = 0.0, var = 0.0, n = 0.0;
      for (size_t k = 0; k < g_.pixel_count(); ++k) {
        if (!g_.covered(k)) continue;
        diff += e1.grey[k] - r.ao[k];
        const double d12 = static_cast<double>(e1.grey[k]) - e2.grey[k];
        var += 0.5 * d12 * d12 + static_cast<double>(r.stderr_ao[k]) * r.stderr_ao[k];
        n += 1.0;
      }
      ASSERT_GT(n, 2000.0);
      EXPECT_NEAR(diff / n, 0.0, 4.0 * std::sqrt(var) / n)
          << falloff_name(rho) << " " << sampler_name(sampling);
    }
}

TEST_F(SmallScene, DeterministicWhateverTheThreadCount) {
  for (auto sampling : kSamplings) {
    ObscuranceSettings s = settings(Falloff::sqrt, sampling, 0.6);
    s.seed = 42;
    const ObscuranceImage many = compute_obscurances(es_, g_, s, glm::vec3(0.5f));
    ObscuranceImage one;
    {
      tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
      one = compute_obscurances(es_, g_, s, glm::vec3(0.5f));
    }
    EXPECT_EQ(many.grey, one.grey);
    EXPECT_EQ(many.rgb, one.rgb);
    s.seed = 43;
    EXPECT_NE(compute_obscurances(es_, g_, s, glm::vec3(0.5f)).grey, many.grey);
  }
}

// A floor (albedo f) and a parallel disk (albedo cd) of radius a at height h above the probe, with
// h < dmax < sqrt(a^2 + h^2): the disk counts only inside the cone cos(theta) > c = h / dmax.
// With u = cos(theta), (1/pi) Int value cos(theta) dw = 2 Int_0^1 value(u) u du, and a ray inside
// the cone hits at d = h / u, x = d / dmax = c / u:
//   W = c^2 + 2 Int_c^1 rho(c/u) u du            (the rim and the open sky are worth 1)
//   sqrt:     2 sqrt(c) Int_c^1 u^(1/2) du = (4/3)(sqrt(c) - c^2)  ->  W = (4/3) sqrt(c) - c^2 / 3
//   constant: W = c^2 (the reference test's h^2 / dmax^2)
//   exp:      no elementary form (an exponential integral): Simpson's rule, error << 1e-9
// Colour (eq. 5-6): the cone is worth cd rho(c/u), the rest R_ave: W_rgb = cd (W - c^2) + R_ave
// c^2.
class DiskAbovePlane : public ::testing::Test {
 protected:
  static constexpr double a = 1.0, h = 0.5, dmax = 0.85, c = h / dmax;
  static constexpr int kPixels = 1024;
  const glm::vec3 floor_albedo{0.2f, 0.6f, 0.4f}, disk_albedo{0.9f, 0.1f, 0.5f};
  DiskAbovePlane()
      : scene_(scene_of(
            {generated("floor", "plane", {{"size", {20, 20}}}, glm::vec3(0.0f), floor_albedo),
             generated("disk", "disk", {{"radius", a}, {"segments", 4096}, {"facing", "down"}},
                       {0.0f, static_cast<float>(h), 0.0f}, disk_albedo)})),
        es_(scene_),
        g_(probe({0, 0, 0}, {0, 1, 0}, kPixels)) {}
  static double exact(Falloff rho) {
    switch (rho.kind) {
      case Falloff::Kind::none:
        return c * c;
      case Falloff::Kind::sqrt:
        return 4.0 / 3.0 * std::sqrt(c) - c * c / 3.0;
      case Falloff::Kind::power:  // K != 2; derived in references/reference_test.cpp (c0 = q = c)
        return c * c + 2.0 * std::pow(c, rho.k) * (1.0 - std::pow(c, 2.0 - rho.k)) / (2.0 - rho.k);
      case Falloff::Kind::exp: {
        const int n = 20000;  // even; the integrand is smooth on [c, 1]
        const double step = (1.0 - c) / n;
        auto f = [](double u) {
          return (1.0 - std::exp(-4.0 * c / u)) / (1.0 - std::exp(-4.0)) * u;
        };
        double sum = f(c) + f(1.0);
        for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(c + i * step);
        return c * c + 2.0 * sum * step / 3.0;
      }
      default:
        return -1.0;
    }
  }
  glm::dvec3 r_ave() const {
    const double af = scene_.objects[0].facts["area"], ad = scene_.objects[1].facts["area"];
    return (af * glm::dvec3(floor_albedo) + ad * glm::dvec3(disk_albedo)) / (af + ad);
  }
  Scene scene_;
  EmbreeScene es_;
  GBuffer g_;
};

TEST_F(DiskAbovePlane, AverageReflectivityIsTheAreaWeightedMean) {
  // eq. 3 from the generators' exact areas; the mesh's float vertices differ by ~1e-7 relative.
  const glm::vec3 got = average_reflectivity(scene_);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got[ch], r_ave()[ch], 1e-5);
}

TEST_F(DiskAbovePlane, GreyAndColourMatchTheClosedForms) {
  const glm::vec3 ra = average_reflectivity(scene_);
  for (auto rho : kRhos)
    for (auto sampling : kSamplings) {
      const ObscuranceImage o = compute_obscurances(es_, g_, settings(rho, sampling, dmax), ra);
      const double w = exact(rho);
      const Pooled grey = pooled(kPixels, [&](size_t k) { return o.grey[k]; });
      EXPECT_NEAR(grey.mean, w, 4.0 * grey.stderr_of_mean + 1e-6)
          << falloff_name(rho) << " " << sampler_name(sampling);
      for (int ch = 0; ch < 3; ++ch) {
        const double expected = disk_albedo[ch] * (w - c * c) + ra[ch] * c * c;
        const Pooled rgb = pooled(kPixels, [&](size_t k) { return o.rgb[k][ch]; });
        EXPECT_NEAR(rgb.mean, expected, 4.0 * rgb.stderr_of_mean + 1e-6)
            << falloff_name(rho) << " " << sampler_name(sampling) << " channel " << ch;
      }
    }
}

// The distribution of a per-pixel value, exactly: {value, probability} pairs.
struct Exact {
  double variance, fourth_moment;
};
Exact exact_moments(const std::vector<std::pair<double, double>>& law) {
  double mean = 0.0, m2 = 0.0, m4 = 0.0;
  for (const auto& [v, p] : law) mean += p * v;
  for (const auto& [v, p] : law) {
    m2 += p * (v - mean) * (v - mean);
    m4 += p * std::pow(v - mean, 4);
  }
  return {m2, m4};
}
// The standard deviation of the sample variance of n i.i.d. values with these moments.
double sample_variance_spread(const Exact& e, double n) {
  return std::sqrt((e.fourth_moment - e.variance * e.variance * (n - 3.0) / (n - 1.0)) / n);
}

TEST_F(DiskAbovePlane, SystematicSamplingHasLowerVarianceForTheSmoothRhos) {
  // §4.2, Fig. 6. With sqrt and exp the integrand is continuous (rho(1) = 1 at the cut), where
  // stratification pays. Over 1024 independent pixels a sample variance is known to within about
  // sqrt(2 / 1023) = 4.4% (x ~2 for these non-normal values), so the log of a ratio of two has a
  // sampling spread of about 0.15. The measured ratios at 16 rays are 0.030 (sqrt) and 0.042
  // (exp); requiring < 0.25 sits more than 10 such spreads above them and still asserts a
  // factor-4 variance reduction.
  for (auto rho : {Falloff::sqrt, Falloff::exp}) {
    const ObscuranceImage r =
        compute_obscurances(es_, g_, settings(rho, SamplerKind::random, dmax), glm::vec3(0.5f));
    const ObscuranceImage s =
        compute_obscurances(es_, g_, settings(rho, SamplerKind::stratified, dmax), glm::vec3(0.5f));
    const double vr = pooled(kPixels, [&](size_t k) { return r.grey[k]; }).variance;
    const double vs = pooled(kPixels, [&](size_t k) { return s.grey[k]; }).variance;
    EXPECT_LT(vs, 0.25 * vr) << falloff_name(rho) << ": systematic " << vs << ", random " << vr;
  }
}

TEST(Obscurances, SystematicSamplingOfAnAlignedConeHasItsClosedFormVariance) {
  // rho = constant under the disk: a ray counts as hit iff it lies in the cone cos(theta) > c.
  // Malley's lift of the concentric map sends the centred square max(|2u-1|, |2v-1|) < r onto the
  // disk of radius r = sin(theta_D) = sqrt(1 - c^2): the cone is exactly the square
  // [(1-r)/2, (1+r)/2)^2 of the unit square, aligned with the systematic grid. With one offset
  // shared by the 4 x 4 cells, the number of points inside is nx * ny, nx and ny independent,
  // each floor(4r) + 1 with probability frac(4r) and floor(4r) otherwise; the grey value is
  // 1 - nx ny / 16. Random sampling gives a Binomial(16, r^2) count. The closed forms give
  // variances 0.01481 (systematic) and 0.01414 (random): for this cone systematic sampling is NO
  // better (and 1.44x worse at 64 rays, 0.33x at 256): the gain of §4.2 needs integrands that are
  // not discontinuous along the grid. Each measured variance must match its closed form within 4
  // standard deviations of a sample variance of 4096 values, computed from the exact laws.
  const double h = 0.5, dmax = 0.85, c = h / dmax, r = std::sqrt(1.0 - c * c);
  Scene s =
      scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                generated("disk", "disk", {{"radius", 1.0}, {"segments", 4096}, {"facing", "down"}},
                          {0.0f, static_cast<float>(h), 0.0f})});
  EmbreeScene es(s);
  const int pixels = 4096;
  const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, pixels);
  const double k = std::floor(4.0 * r), f = 4.0 * r - k;
  std::vector<std::pair<double, double>> systematic, random;
  for (double nx : {k, k + 1.0})
    for (double ny : {k, k + 1.0})
      systematic.push_back(
          {1.0 - nx * ny / 16.0, (nx == k ? 1.0 - f : f) * (ny == k ? 1.0 - f : f)});
  const double p = r * r;
  for (int hits = 0; hits <= 16; ++hits)
    random.push_back({1.0 - hits / 16.0, std::tgamma(17.0) /
                                             (std::tgamma(hits + 1.0) * std::tgamma(17.0 - hits)) *
                                             std::pow(p, hits) * std::pow(1.0 - p, 16 - hits)});
  for (auto [sampling, law] :
       {std::pair{SamplerKind::stratified, systematic}, std::pair{SamplerKind::random, random}}) {
    const ObscuranceImage o =
        compute_obscurances(es, g, settings(Falloff::none, sampling, dmax), glm::vec3(0.5f));
    const Pooled measured = pooled(pixels, [&](size_t i) { return o.grey[i]; });
    const Exact e = exact_moments(law);
    EXPECT_NEAR(measured.mean, c * c, 4.0 * std::sqrt(e.variance / pixels))
        << sampler_name(sampling);
    EXPECT_NEAR(measured.variance, e.variance, 4.0 * sample_variance_spread(e, pixels))
        << sampler_name(sampling);
  }
}

// Inside a closed box whose walls all have albedo a, R_ave = a too, so every ray is worth
// a * (its grey value): a hit within dmax a rho(d/dmax), anything else R_ave = a. Hence
// W_rgb = a W exactly (up to float rounding); with dmax larger than the box every ray hits and
// rho = constant gives W = W_rgb = 0 (no colour bleeding, §3); with dmax below the distance to
// every wall nothing is in range and W = 1, W_rgb = R_ave = a.
TEST(Obscurances, ClosedBoxColourIsAlbedoTimesGrey) {
  const glm::vec3 albedo(0.2f, 0.5f, 0.8f);
  Scene s = scene_of(
      {generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}}, glm::vec3(0.0f), albedo)});
  EmbreeScene es(s);
  const glm::vec3 ra = average_reflectivity(s);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(ra[ch], albedo[ch], 1e-6);
  const GBuffer g = probe({0.1f, 0.0f, 0.2f}, {0, 1, 0}, 64);
  for (auto rho : kRhos)
    for (auto sampling : kSamplings) {
      const ObscuranceImage o = compute_obscurances(es, g, settings(rho, sampling, 10.0), ra);
      for (size_t k = 0; k < o.grey.size(); ++k) {
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(o.rgb[k][ch], albedo[ch] * o.grey[k], 1e-6);
        if (rho == Falloff::none) {
          EXPECT_EQ(o.grey[k], 0.0f);
          EXPECT_EQ(o.rgb[k], glm::vec3(0.0f));
        } else {
          EXPECT_GT(o.grey[k], 0.0f);  // a far wall is worth rho(d/10) > 0
        }
      }
      // The nearest wall is 0.8 away from the probe (x = 1 wall at 0.9, z = 1 wall at 0.8).
      const ObscuranceImage open = compute_obscurances(es, g, settings(rho, sampling, 0.75), ra);
      for (size_t k = 0; k < open.grey.size(); ++k) {
        EXPECT_EQ(open.grey[k], 1.0f);
        for (int ch = 0; ch < 3; ++ch) EXPECT_FLOAT_EQ(open.rgb[k][ch], ra[ch]);
      }
    }
}

TEST(Obscurances, NothingInRangeGivesTheAverageReflectivity) {
  // eq. 6 with two albedos: the red block lies 3 units away, beyond dmax = 1.
  Scene s = scene_of({generated("floor", "plane", {{"size", {10, 10}}}, glm::vec3(0.0f),
                                glm::vec3(0.3f, 0.3f, 0.9f)),
                      generated("block", "box", nlohmann::json::object(), {3.0f, 0.0f, 0.0f},
                                glm::vec3(1.0f, 0.0f, 0.0f))});
  EmbreeScene es(s);
  const double af = s.objects[0].facts["area"], ab = s.objects[1].facts["area"];
  const glm::vec3 expected((0.3 * af + 1.0 * ab) / (af + ab), 0.3 * af / (af + ab),
                           0.9 * af / (af + ab));
  const glm::vec3 ra = average_reflectivity(s);
  const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 32);
  for (auto rho : kRhos) {
    const ObscuranceImage o =
        compute_obscurances(es, g, settings(rho, SamplerKind::stratified, 1.0), ra);
    for (size_t k = 0; k < o.grey.size(); ++k) {
      EXPECT_EQ(o.grey[k], 1.0f);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(o.rgb[k][ch], expected[ch], 1e-6);
    }
  }
}

TEST(Obscurances, DeclarationMapsRhoOntoTheFalloffs) {
  const EstimatorInfo& e = find_estimator("obscurances");
  auto definition = [&](std::vector<std::string> sets) {
    return e.definition(resolve_params(e.name, e.params, parse_set_arguments(sets), "--set"));
  };
  const AoDefinition d = definition({});
  EXPECT_EQ(d.weighting, Weighting::cosine);
  EXPECT_EQ(d.falloff, Falloff::sqrt);
  EXPECT_DOUBLE_EQ(d.dmax, 1.0);
  EXPECT_EQ(definition({"rho=constant", "dmax=0.3"}).falloff, Falloff::none);
  EXPECT_DOUBLE_EQ(definition({"rho=constant", "dmax=0.3"}).dmax, 0.3);
  EXPECT_EQ(definition({"rho=exp"}).falloff, Falloff::exp);
  EXPECT_EQ(definition({"rho=power", "rho_k=3"}).falloff, Falloff::power(3.0));
  EXPECT_EQ(definition({"rho=power", "rho_k=1"}).falloff, Falloff::linear);
  EXPECT_THROW(definition({"rho=power", "rho_k=0"}), InputError);
  EXPECT_THROW(definition({"rho=linear"}), InputError);
  EXPECT_THROW(definition({"dmax=0"}), InputError);
  EXPECT_THROW(definition({"sampling=sobol"}), InputError);
}

TEST(Obscurances, EstimatorWritesTheGreyAndTheColourChannels) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                      generated("ball", "sphere", {{"radius", 0.5}}, {0.0f, 0.5f, 0.0f},
                                glm::vec3(0.1f, 0.8f, 0.3f))});
  EmbreeScene es(s);
  View v;
  v.eye = {0.0f, 1.5f, 2.5f};
  v.target = {0.0f, 0.3f, 0.0f};
  const GBuffer g = render_gbuffer(es, make_camera(v, 32, 24));
  const EstimatorInfo& e = find_estimator("obscurances");
  const ParamSet p =
      resolve_params(e.name, e.params, parse_set_arguments({"dmax=0.7", "rays=8"}), "--set");
  auto estimator = e.create(p);
  const EstimateContext context{s, es, g};
  estimator->prepare(context);
  const EstimateResult r = estimator->run(context);
  const ObscuranceImage o = compute_obscurances(
      es, g, settings(Falloff::sqrt, SamplerKind::stratified, 0.7, 8), average_reflectivity(s));
  EXPECT_EQ(r.ao, o.grey);
  const char* names[3] = {"obscurance.R", "obscurance.G", "obscurance.B"};
  for (int ch = 0; ch < 3; ++ch) {
    ASSERT_EQ(r.extra_channels.count(names[ch]), 1u) << names[ch];
    const std::vector<float>& channel = r.extra_channels.at(names[ch]);
    for (size_t k = 0; k < channel.size(); ++k) EXPECT_EQ(channel[k], o.rgb[k][ch]);
  }
  EXPECT_EQ(estimator->run(context).ao, r.ao);  // repeatable frames
}

}  // namespace
}  // namespace aoeval
