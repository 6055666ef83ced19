// The reference against closed forms (CONTRACT §3), with tolerances from the sample count: every
// analytic check pools many independent pixels and allows 4 standard errors of the pooled mean
// (a false alarm about once in 16,000 runs), computed from the reference's own reported stderr.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "base/errors.h"
#include "references/reference.h"
#include "scenes/analytic_scenes.h"
#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

struct Pooled {
  double mean, stderr_of_mean;
};

Pooled pooled(const ReferenceImage& r) {
  double sum = 0.0, se2 = 0.0;
  for (size_t k = 0; k < r.ao.size(); ++k) {
    sum += r.ao[k];
    se2 += static_cast<double>(r.stderr_ao[k]) * r.stderr_ao[k];
  }
  const double n = static_cast<double>(r.ao.size());
  return {sum / n, std::sqrt(se2) / n};
}

ReferenceSettings settings(Weighting w, SamplerKind sampler, int spp = 256) {
  ReferenceSettings s;
  s.spp = spp;
  s.definition.weighting = w;
  s.sampler = sampler;
  return s;
}

const SamplerKind kSamplers[] = {SamplerKind::random, SamplerKind::stratified, SamplerKind::sobol};
const Weighting kWeightings[] = {Weighting::cosine, Weighting::uniform};

TEST(Reference, OpenPlaneIsFullyOpen) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {100, 100}}})});
  EmbreeScene es(s);
  const GBuffer g = probe({0.3f, 0.0f, -0.2f}, {0, 1, 0}, 16);
  for (auto w : kWeightings)
    for (auto k : kSamplers) {
      const ReferenceImage r = compute_reference(es, g, settings(w, k, 64));
      for (size_t i = 0; i < r.ao.size(); ++i) {
        EXPECT_EQ(r.ao[i], 1.0f);
        EXPECT_EQ(r.stderr_ao[i], 0.0f);
        // By symmetry the bent normal is the normal (0, 1, 0) for both weightings; the estimate
        // tilts by the mean t of the n directions' tangent components. Each component has variance
        // s2 = E[x^2] (cosine 1/4, uniform 1/3) and the normal component mean mu (cosine 2/3,
        // uniform 1/2), so n |t|^2 / s2 ~ chi^2 with 2 degrees of freedom: |t|^2 <= 2 ln(1/p) s2 /
        // n but with probability p (1e-6 per pixel), and 1 - bent.y <= |t|^2 / (2 mu^2).
        const double s2 = w == Weighting::cosine ? 0.25 : 1.0 / 3.0;
        const double mu = w == Weighting::cosine ? 2.0 / 3.0 : 0.5;
        const double t2 = 2.0 * std::log(1e6) * s2 / 64.0;
        EXPECT_NEAR(r.bent[i].y, 1.0, t2 / (2.0 * mu * mu)) << sampler_name(k);
        EXPECT_NEAR(glm::length(r.bent[i]), 1.0, 1e-5);
      }
    }
}

// The bent normal knows its own noise (reference.h, bent_stderr). On an open plane every sample is
// unoccluded, the true bent normal is the normal, and each pixel's angle from it is the
// reference's angular error alone, so over many pixels mean(angle^2) must equal
// mean(bent_stderr^2). Per pixel angle^2 is about (s^2 / 2) chi^2 with 2 degrees of freedom
// (exponential: its standard deviation equals its mean), so the mean over M = 2048 pixels has a
// relative standard error of 1/sqrt(M) = 2.2 %: 4 of them, plus 4 % for the spread of the
// per-pixel stderr estimates themselves (64 samples or 8 replicates each) allow a ratio within
// 0.8 .. 1.2. For i.i.d. cosine samples the closed form is s = sqrt(E[sin^2] / n) / E[cos] =
// sqrt(1/2 / 64) / (2/3) rad = 7.60 degrees.
TEST(Reference, BentNormalStderrMatchesItsScatter) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {100, 100}}})});
  EmbreeScene es(s);
  const GBuffer g = probe({0.3f, 0.0f, -0.2f}, {0, 1, 0}, 2048);
  for (auto k : {SamplerKind::random, SamplerKind::sobol}) {
    const ReferenceImage r = compute_reference(es, g, settings(Weighting::cosine, k, 64));
    ASSERT_EQ(r.bent_stderr.size(), r.ao.size());
    double angle2 = 0.0, stderr2 = 0.0;
    for (size_t i = 0; i < r.ao.size(); ++i) {
      const double c = std::min(1.0, static_cast<double>(glm::normalize(r.bent[i]).y));
      const double angle = std::acos(c) * 180.0 / 3.14159265358979;
      angle2 += angle * angle;
      stderr2 += static_cast<double>(r.bent_stderr[i]) * r.bent_stderr[i];
    }
    const double n = static_cast<double>(r.ao.size());
    const double ratio = std::sqrt(angle2 / stderr2);
    std::printf("%s: rms angle %.3f deg, rms bent_stderr %.3f deg, ratio %.3f\n", sampler_name(k),
                std::sqrt(angle2 / n), std::sqrt(stderr2 / n), ratio);
    EXPECT_GT(ratio, 0.8);
    EXPECT_LT(ratio, 1.2);
    if (k == SamplerKind::random) {
      EXPECT_NEAR(std::sqrt(stderr2 / n), 7.60, 0.3);
    }
  }
}

TEST(Reference, InsideAClosedBoxIsFullyOccluded) {
  Scene s = scene_of({generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}})});
  EmbreeScene es(s);
  const GBuffer g = probe({0.1f, 0.0f, 0.2f}, {0, 1, 0}, 16);
  for (auto w : kWeightings)
    for (auto k : kSamplers) {
      const ReferenceImage r = compute_reference(es, g, settings(w, k, 64));
      for (size_t i = 0; i < r.ao.size(); ++i) {
        EXPECT_EQ(r.ao[i], 0.0f);
        EXPECT_EQ(r.bent[i], glm::vec3(0.0f));
      }
    }
}

// A floor and a parallel disk of radius a at height h above the probe (a 4096-gon: its solid angle
// differs from the circle's by < 1e-6 relative).
class DiskAbovePlane : public ::testing::Test {
 protected:
  static constexpr double a = 1.0, h = 0.5;
  DiskAbovePlane()
      : scene_(scene_of(
            {generated("floor", "plane", {{"size", {20, 20}}}),
             generated("disk", "disk", {{"radius", a}, {"segments", 4096}, {"facing", "down"}},
                       {0.0f, static_cast<float>(h), 0.0f})})),
        es_(scene_) {}
  void expect(const ReferenceSettings& s, double exact) {
    const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 256);
    const Pooled p = pooled(compute_reference(es_, g, s));
    EXPECT_NEAR(p.mean, exact, 4.0 * p.stderr_of_mean + 1e-6)
        << s.definition.label() << " " << sampler_name(s.sampler);
  }
  Scene scene_;
  EmbreeScene es_;
};

TEST_F(DiskAbovePlane, BothWeightingsMatchTheSolidAngleClosedForms) {
  // cosine: the disk covers a cone of half-angle alpha, tan(alpha) = a / h, whose projected solid
  // angle is pi sin^2(alpha): AO = 1 - sin^2(alpha) = h^2 / (a^2 + h^2).
  // uniform: its solid angle is 2 pi (1 - cos(alpha)): AO = cos(alpha) = h / sqrt(a^2 + h^2).
  for (auto k : kSamplers) {
    expect(settings(Weighting::cosine, k), h * h / (a * a + h * h));
    expect(settings(Weighting::uniform, k), h / std::sqrt(a * a + h * h));
  }
}

TEST_F(DiskAbovePlane, DmaxCuttingTheRimMatchesItsClosedForms) {
  // With h < dmax < sqrt(a^2 + h^2), the disk counts only where h / cos(theta) < dmax, a cone with
  // cos(theta_D) = h / dmax: cosine AO = h^2 / dmax^2, uniform AO = h / dmax.
  const double d = 0.85;  // not a dyadic cut: nets would integrate it exactly
  for (auto k : kSamplers) {
    ReferenceSettings c = settings(Weighting::cosine, k), u = settings(Weighting::uniform, k);
    c.definition.dmax = u.definition.dmax = d;
    expect(c, h * h / (d * d));
    expect(u, h / d);
    // Linear falloff: a ray hitting at h / cos(theta) < dmax is worth h / (dmax cos(theta)):
    // AO = (2h/dmax)(1 - h/dmax) + h^2/dmax^2 = 2h/dmax - h^2/dmax^2.
    c.definition.falloff = Falloff::linear;
    expect(c, 2 * h / d - h * h / (d * d));
  }
}

// power:K (CONTRACT §3, rho(x) = x^K). Derivation, with c = cos(theta) of a direction, the disk of
// radius a at height h (cos(alpha) = h / sqrt(a^2 + h^2)) and q = h / dmax: a direction with
// c > cos(alpha) hits the disk at t = h / c, which counts when t < dmax, i.e. c > q. So the rays
// with c in [c0, 1], c0 = max(cos(alpha), q), are worth rho(t / dmax) = (q / c)^K, all others 1.
//   cosine:  (1/pi) Int v cos dw = Int_0^1 v 2c dc
//            AO = c0^2 + 2 q^K Int_c0^1 c^(1-K) dc
//               = c0^2 + 2 q^K (1 - c0^(2-K)) / (2 - K)    (K != 2),  c0^2 - 2 q^2 ln(c0)  (K = 2)
//   uniform: (1/2pi) Int v dw = Int_0^1 v dc
//            AO = c0 + q^K (1 - c0^(1-K)) / (1 - K)        (K != 1),  c0 - q ln(c0)     (K = 1)
// (K = 1 with c0 = q gives the linear case above, 2q - q^2.)
double power_cosine_ao(double k, double c0, double q) {
  if (k == 2.0) return c0 * c0 - 2.0 * q * q * std::log(c0);
  return c0 * c0 + 2.0 * std::pow(q, k) * (1.0 - std::pow(c0, 2.0 - k)) / (2.0 - k);
}
double power_uniform_ao(double k, double c0, double q) {
  if (k == 1.0) return c0 - q * std::log(c0);
  return c0 + std::pow(q, k) * (1.0 - std::pow(c0, 1.0 - k)) / (1.0 - k);
}

TEST_F(DiskAbovePlane, PowerFalloffsMatchTheirClosedForms) {
  const double cos_alpha = h / std::sqrt(a * a + h * h);
  // 0.85 cuts the rim (c0 = q); 2.5 lies beyond it (c0 = cos(alpha), the whole disk counts).
  for (double d : {0.85, 2.5})
    for (double k : {2.0, 3.0})
      for (auto sampler : kSamplers) {
        const double q = h / d, c0 = std::max(cos_alpha, q);
        ReferenceSettings c = settings(Weighting::cosine, sampler);
        ReferenceSettings u = settings(Weighting::uniform, sampler);
        c.definition.dmax = u.definition.dmax = d;
        c.definition.falloff = u.definition.falloff = Falloff::power(k);
        expect(c, power_cosine_ao(k, c0, q));
        expect(u, power_uniform_ao(k, c0, q));
      }
}

TEST_F(DiskAbovePlane, PowerOneIsLinearAndPowerHalfIsSqrt) {
  // One definition, one name: the same label (the reference cache key) and the same bits.
  EXPECT_EQ(Falloff::power(1.0), Falloff::linear);
  EXPECT_EQ(Falloff::power(0.5), Falloff::sqrt);
  EXPECT_EQ(parse_falloff("power:1"), Falloff::linear);
  EXPECT_EQ(parse_falloff("power:0.5"), Falloff::sqrt);
  ReferenceSettings linear = settings(Weighting::cosine, SamplerKind::sobol, 16);
  linear.definition.dmax = 0.85;
  linear.definition.falloff = Falloff::linear;
  ReferenceSettings one = linear;
  one.definition.falloff = parse_falloff("power:1");
  EXPECT_EQ(one.definition, linear.definition);
  EXPECT_EQ(one.definition.to_json(), linear.definition.to_json());  // the cache key's part
  EXPECT_EQ(one.definition.label(), linear.definition.label());
  const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 16);
  EXPECT_EQ(compute_reference(es_, g, one).ao, compute_reference(es_, g, linear).ao);
}

TEST(Reference, ConvexObjectsOutsideIsOpenEverywhere) {
  // Every covered pixel of a convex object, with the geometric hemisphere, sees no occluder: AO is
  // exactly 1. This also pins the origin offset: one self-intersection would show as AO < 1.
  for (const char* gen : {"box", "sphere"}) {
    Scene s =
        scene_of({generated("convex", gen, nlohmann::json::object(), {37.0f, 11.0f, -23.0f})});
    EmbreeScene es(s);
    View v;
    v.eye = {39.5f, 12.8f, -20.0f};
    v.target = {37.0f, 11.3f, -23.0f};
    const GBuffer g = render_gbuffer(es, make_camera(v, 48, 36));
    ReferenceSettings st = settings(Weighting::cosine, SamplerKind::random, 64);
    st.normal = NormalMode::geometric;
    const ReferenceImage r = compute_reference(es, g, st);
    size_t covered = 0;
    for (size_t k = 0; k < r.ao.size(); ++k) {
      if (!g.covered(k)) continue;
      ++covered;
      ASSERT_EQ(r.ao[k], 1.0f) << gen << " pixel " << k;
    }
    EXPECT_GT(covered, 150u) << gen;
  }
}

TEST(Reference, GrazingViewOfAFarPlaneHasNoSelfIntersection) {
  // Large coordinates and grazing primary rays: the hardest case for origin offsets.
  Scene s =
      scene_of({generated("floor", "plane", {{"size", {400, 400}}}, {1000.0f, 50.0f, -700.0f})});
  EmbreeScene es(s);
  View v;
  v.eye = {1000.0f, 50.5f, -560.0f};
  v.target = {1000.0f, 50.0f, -700.0f};
  const GBuffer g = render_gbuffer(es, make_camera(v, 64, 48));
  const ReferenceImage r =
      compute_reference(es, g, settings(Weighting::cosine, SamplerKind::random, 64));
  for (size_t k = 0; k < r.ao.size(); ++k)
    if (g.covered(k)) {
      ASSERT_EQ(r.ao[k], 1.0f) << "pixel " << k;
    }
}

TEST(Reference, StandardErrorIsCalibratedForEverySampler) {
  // Over many seeds, the spread of each pixel's value must match the stderr it reports (RMS over
  // seeds) within 20%. With 400 seeds the empirical std itself is known to about 3.5%.
  Scene s =
      scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                generated("disk", "disk", {{"radius", 1.0}, {"segments", 256}, {"facing", "down"}},
                          {0.0f, 0.5f, 0.0f})});
  EmbreeScene es(s);
  GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 4);
  for (int i = 0; i < 4; ++i) g.position[i] = {0.35f * i, 0.0f, 0.0f};  // AO from ~0.2 to ~0.6
  const int seeds = 400;
  for (auto k : kSamplers) {
    std::vector<double> sum(4, 0.0), sum_sq(4, 0.0), se2(4, 0.0);
    for (int seed = 1; seed <= seeds; ++seed) {
      ReferenceSettings st = settings(Weighting::cosine, k, 64);
      st.seed = static_cast<uint64_t>(seed);
      const ReferenceImage r = compute_reference(es, g, st);
      for (int i = 0; i < 4; ++i) {
        sum[i] += r.ao[i];
        sum_sq[i] += static_cast<double>(r.ao[i]) * r.ao[i];
        se2[i] += static_cast<double>(r.stderr_ao[i]) * r.stderr_ao[i];
      }
    }
    for (int i = 0; i < 4; ++i) {
      const double mean = sum[i] / seeds;
      const double spread = std::sqrt((sum_sq[i] - seeds * mean * mean) / (seeds - 1));
      const double reported = std::sqrt(se2[i] / seeds);
      EXPECT_NEAR(reported / spread, 1.0, 0.2) << sampler_name(k) << " pixel " << i << ": spread "
                                               << spread << ", reported " << reported;
    }
  }
}

TEST(Reference, DeterministicWhateverTheThreadCount) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                      generated("ball", "sphere", {{"radius", 0.5}}, {0.0f, 0.5f, 0.0f})});
  EmbreeScene es(s);
  View v;
  v.eye = {0.0f, 1.5f, 2.5f};
  v.target = {0.0f, 0.3f, 0.0f};
  const GBuffer g = render_gbuffer(es, make_camera(v, 40, 30));
  for (auto k : kSamplers) {
    ReferenceSettings st = settings(Weighting::cosine, k, 32);
    st.seed = 42;
    const ReferenceImage many = compute_reference(es, g, st);
    ReferenceImage one;
    {
      tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
      one = compute_reference(es, g, st);
    }
    EXPECT_EQ(many.ao, one.ao) << sampler_name(k);
    EXPECT_EQ(many.stderr_ao, one.stderr_ao) << sampler_name(k);
    st.seed = 43;
    EXPECT_NE(compute_reference(es, g, st).ao, many.ao) << sampler_name(k);
  }
}

TEST(Reference, TargetStderrKeepsSamplingUntilMet) {
  Scene s =
      scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                generated("disk", "disk", {{"radius", 1.0}, {"segments", 256}, {"facing", "down"}},
                          {0.0f, 0.5f, 0.0f})});
  EmbreeScene es(s);
  const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 8);
  for (auto k : kSamplers) {
    ReferenceSettings st = settings(Weighting::cosine, k, 64);
    st.target_stderr = 0.01;
    st.max_spp = 1 << 16;
    const ReferenceImage r = compute_reference(es, g, st);
    for (size_t i = 0; i < r.ao.size(); ++i) {
      EXPECT_LE(r.stderr_ao[i], 0.01f) << sampler_name(k);
      EXPECT_GT(r.spp[i], 64.0f) << sampler_name(k);  // 64 rays alone give ~0.05
    }
    st.max_spp = 128;  // the cap wins over the target
    const ReferenceImage capped = compute_reference(es, g, st);
    for (size_t i = 0; i < capped.ao.size(); ++i) EXPECT_EQ(capped.spp[i], 128.0f);
  }
}

TEST(AoDefinition, RayValuesAtTheEnds) {
  AoDefinition d;
  d.dmax = 2.0;
  for (Falloff f : {Falloff::none, Falloff::linear, Falloff::sqrt, Falloff::exp}) {
    d.falloff = f;
    EXPECT_EQ(d.ray_value(0.0f), 0.0f) << falloff_name(f);
    EXPECT_EQ(d.ray_value(2.0f), 1.0f) << falloff_name(f);
    EXPECT_EQ(d.ray_value(INFINITY), 1.0f) << falloff_name(f);
    EXPECT_NEAR(d.ray_value(1.9999f), f == Falloff::none ? 0.0f : 1.0f, 2e-4) << falloff_name(f);
  }
  d.falloff = Falloff::linear;
  EXPECT_FLOAT_EQ(d.ray_value(0.5f), 0.25f);
  d.falloff = Falloff::sqrt;
  EXPECT_FLOAT_EQ(d.ray_value(0.5f), 0.5f);
  d.falloff = Falloff::power(3.0);
  EXPECT_FLOAT_EQ(d.ray_value(1.0f), 0.125f);
  EXPECT_EQ(d.ray_value(2.0f), 1.0f);
  EXPECT_EQ(falloff_name(d.falloff), "power:3");
  EXPECT_EQ(d.label(), "cosine/dmax:2/power:3");
  for (const char* text : {"power:3", "power:0.25", "power:2.5", "power:1.5"})
    EXPECT_EQ(falloff_name(parse_falloff(text)), text);
  for (const char* bad : {"power:0", "power:-1", "power:nan", "power:inf", "power:x",
                          "power:", "power:2 ", "power", "cubic"})
    EXPECT_THROW(parse_falloff(bad), InputError) << bad;
  EXPECT_THROW(Falloff::power(0.0), InputError);
  EXPECT_THROW(Falloff::power(std::nan("")), InputError);
  AoDefinition unbounded;
  unbounded.falloff = Falloff::linear;
  EXPECT_THROW(validate_definition(unbounded), InputError);
}

}  // namespace
}  // namespace aoeval

namespace aoeval {
namespace {

// Bit-for-bit equality of two float vectors (EXPECT_EQ on floats would equate +0 and -0).
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}
bool same_bits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

// Issue 42, must-show 3: one trace for several definitions (compute_references) gives each
// definition the very bits of its own trace (compute_reference), for both weightings, falloffs
// none, linear, sqrt, exp and power:3, and three ranges (0.3 and 0.85 cut the tree's hits in the
// middle of their spread; one is unbounded), with a sampler over replicates (sobol) and one over
// samples (random). A small tree over a floor seen through a camera gives every distance.
TEST(References, SharedTraceIsEachDefinitionsOwnTraceBitForBit) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {20, 20}}}),
                      generated("tree", "tree", {{"depth", 3}, {"leaves_per_twig", 4}})});
  EmbreeScene es(s);
  View v;
  v.eye = {0.0f, 2.0f, 6.0f};
  v.target = {0.0f, 1.5f, 0.0f};
  const GBuffer g = render_gbuffer(es, make_camera(v, 40, 32));
  const double inf = std::numeric_limits<double>::infinity();
  for (auto w : kWeightings) {
    std::vector<AoDefinition> defs = {{w, inf, Falloff::none}};
    for (double dmax : {0.3, 0.85})
      for (Falloff f : {Falloff::none, Falloff::linear, Falloff::sqrt, Falloff::exp})
        defs.push_back({w, dmax, f});
    defs.push_back({w, 0.85, Falloff::power(3.0)});
    for (auto sampler : {SamplerKind::sobol, SamplerKind::random}) {
      const ReferenceSettings st = settings(w, sampler, 64);
      const std::vector<ReferenceImage> shared = compute_references(es, g, st, defs);
      ASSERT_EQ(shared.size(), defs.size());
      for (size_t d = 0; d < defs.size(); ++d) {
        ReferenceSettings one = st;
        one.definition = defs[d];
        const ReferenceImage alone = compute_reference(es, g, one);
        const std::string what = defs[d].label() + " " + sampler_name(sampler);
        EXPECT_TRUE(same_bits(shared[d].ao, alone.ao)) << what;
        EXPECT_TRUE(same_bits(shared[d].stderr_ao, alone.stderr_ao)) << what;
        EXPECT_TRUE(same_bits(shared[d].bent, alone.bent)) << what;
        EXPECT_TRUE(same_bits(shared[d].bent_stderr, alone.bent_stderr)) << what;
        EXPECT_TRUE(same_bits(shared[d].spp, alone.spp)) << what;
        // One pass: the shared trace sent the rays one definition alone sends.
        EXPECT_EQ(shared[d].rays_traced, alone.rays_traced) << what;
      }
      // The definitions do differ on this scene (else equality would prove nothing): each
      // bounded one is lighter than the unbounded one, and the falloffs of one range differ.
      for (size_t d = 1; d < defs.size(); ++d)
        EXPECT_FALSE(same_bits(shared[d].ao, shared[0].ao)) << defs[d].label();
      EXPECT_FALSE(same_bits(shared[1].ao, shared[2].ao));
      EXPECT_FALSE(same_bits(shared[2].ao, shared[3].ao));
    }
  }
}

TEST(References, SharedTraceRejectsMixedWeightings) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {20, 20}}})});
  EmbreeScene es(s);
  const GBuffer g = probe({0, 0, 0}, {0, 1, 0}, 4);
  const std::vector<AoDefinition> mixed = {{Weighting::cosine}, {Weighting::uniform}};
  EXPECT_THROW(
      compute_references(es, g, settings(Weighting::cosine, SamplerKind::sobol, 16), mixed),
      InputError);
}

}  // namespace
}  // namespace aoeval
