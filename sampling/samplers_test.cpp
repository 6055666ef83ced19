// Tests of the reference's hemisphere samplers (samplers.h): determinism, the structure of each
// point set (the systematic grid of Méndez et al. 2003 §4.2; (0, m, 2)-nets preserved by the Owen
// scrambling of Burley 2020), unbiasedness and variance, the hemisphere maps (Malley's method on
// the concentric disk of Shirley & Chiu 1997; uniform) against closed-form integrals, and the
// frames of Duff et al. 2017.
//
// Statistical checks use fixed seeds, so each is deterministic; their tolerances are 4 standard
// errors computed from the sample count (a false failure, were the seeds drawn afresh, has
// probability about 6e-5 per check), or chi-square quantiles at p ~ 1e-6.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "base/errors.h"
#include "sampling/samplers.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

constexpr SamplerKind kAllKinds[] = {SamplerKind::random, SamplerKind::stratified,
                                     SamplerKind::sobol};
constexpr double kPi = std::numbers::pi;
constexpr float kOneMinus = 0x1.fffffep-1f;

std::vector<glm::vec2> points(SamplerKind kind, uint64_t seed, uint64_t pixel, uint32_t replicate,
                              uint32_t m) {
  std::vector<glm::vec2> p(m);
  sample_square(kind, seed, pixel, replicate, m, p.data());
  return p;
}

bool same_bits(const std::vector<glm::vec2>& a, const std::vector<glm::vec2>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec2)) == 0;
}

// The grid the brief fixes, computed independently by brute force: n1 = the largest divisor of m
// that is <= sqrt(m), n2 = m / n1.
std::pair<uint32_t, uint32_t> expected_grid(uint32_t m) {
  uint32_t n1 = 1;
  for (uint32_t d = 1; static_cast<uint64_t>(d) * d <= m; ++d)
    if (m % d == 0) n1 = d;
  return {n1, m / n1};
}

// Cell index of coordinate u in a grid of n cells; exact (double(u) * n has <= 24 + 29 bits).
uint32_t cell(float u, uint32_t n) {
  return static_cast<uint32_t>(std::floor(static_cast<double>(u) * n));
}

// Mean and variance (unbiased) of a sample.
struct Moments {
  double mean = 0.0, var = 0.0;
};
Moments moments(const std::vector<double>& x) {
  Moments r;
  for (double v : x) r.mean += v;
  r.mean /= static_cast<double>(x.size());
  for (double v : x) r.var += (v - r.mean) * (v - r.mean);
  r.var /= static_cast<double>(x.size() - 1);
  return r;
}

// Chi-square statistic of counts against equal expected counts.
double chi_square(const std::vector<int>& counts, double total) {
  const double expected = total / static_cast<double>(counts.size());
  double chi2 = 0.0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

// ---- names ----

TEST(SamplerNames, ParseRoundTrips) {
  for (SamplerKind k : kAllKinds) EXPECT_EQ(parse_sampler(sampler_name(k)), k);
  EXPECT_STREQ(sampler_name(SamplerKind::random), "random");
  EXPECT_STREQ(sampler_name(SamplerKind::stratified), "stratified");
  EXPECT_STREQ(sampler_name(SamplerKind::sobol), "sobol");
}

TEST(SamplerNames, UnknownNameIsAnInputErrorListingTheChoices) {
  for (const char* bad : {"halton", "", "Sobol", "random "}) {
    try {
      parse_sampler(bad);
      FAIL() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("--sampler"), std::string::npos) << msg;
      for (const char* choice : {"random", "stratified", "sobol"})
        EXPECT_NE(msg.find(choice), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    }
  }
}

// ---- all samplers ----

TEST(SamplerSquare, SameInputsGiveSameBitsWhateverTheCallOrderOrThread) {
  for (SamplerKind k : kAllKinds) {
    for (uint32_t m : {1u, 7u, 32u, 100u, 256u, 1000u}) {
      const auto a = points(k, 42, 1234, 3, m);
      points(k, 42, 999, 0, 4096);  // an unrelated call in between changes nothing
      EXPECT_TRUE(same_bits(a, points(k, 42, 1234, 3, m))) << sampler_name(k) << " m=" << m;
      std::vector<glm::vec2> b;
      std::thread t([&] { b = points(k, 42, 1234, 3, m); });
      t.join();
      EXPECT_TRUE(same_bits(a, b)) << sampler_name(k) << " m=" << m << " on another thread";
    }
  }
}

TEST(SamplerSquare, DifferentSeedPixelOrReplicateGiveDifferentPoints) {
  for (SamplerKind k : kAllKinds) {
    for (uint32_t m : {1u, 32u, 256u}) {
      const auto base = points(k, 42, 1234, 3, m);
      EXPECT_FALSE(same_bits(base, points(k, 43, 1234, 3, m))) << sampler_name(k) << " seed";
      EXPECT_FALSE(same_bits(base, points(k, 42, 1235, 3, m))) << sampler_name(k) << " pixel";
      for (uint32_t r = 0; r < 16; ++r)  // every replicate differs from the next
        EXPECT_FALSE(same_bits(points(k, 42, 1234, r, m), points(k, 42, 1234, r + 1, m)))
            << sampler_name(k) << " replicate " << r;
      EXPECT_FALSE(same_bits(base, points(k, 42, 1234 + (1ull << 40), 3, m)))
          << sampler_name(k) << " high pixel bits";
    }
  }
  // The samplers draw from separate streams: random and sobol for the same key are unrelated.
  EXPECT_FALSE(
      same_bits(points(SamplerKind::random, 1, 2, 3, 1), points(SamplerKind::sobol, 1, 2, 3, 1)));
}

TEST(SamplerSquare, PointsLieInTheHalfOpenUnitSquare) {
  std::vector<glm::vec2> p(5000);
  for (SamplerKind k : kAllKinds) {
    for (uint32_t m : {1u, 2u, 3u, 31u, 64u, 1000u, 4096u, 4099u}) {
      for (uint64_t seed = 0; seed < 50; ++seed) {
        sample_square(k, seed, seed * 7919, static_cast<uint32_t>(seed % 5), m, p.data());
        for (uint32_t i = 0; i < m; ++i) {
          ASSERT_TRUE(p[i].x >= 0.0f && p[i].x < 1.0f && p[i].y >= 0.0f && p[i].y < 1.0f)
              << sampler_name(k) << " m=" << m << " i=" << i << " (" << p[i].x << ", " << p[i].y
              << ")";
        }
      }
    }
  }
}

TEST(SamplerSquare, ZeroPointsWritesNothing) {
  glm::vec2 sentinel(-1.0f, -2.0f);
  for (SamplerKind k : kAllKinds) {
    sample_square(k, 1, 2, 3, 0, &sentinel);
    EXPECT_EQ(sentinel, glm::vec2(-1.0f, -2.0f));
  }
}

// ---- stratified (systematic sampling) ----

// Exactly one point per cell of the n1 x n2 grid, in row-major order, all with the same offset.
void expect_systematic_grid(uint32_t m, uint64_t seed, uint32_t replicate) {
  const auto [n1, n2] = expected_grid(m);
  ASSERT_EQ(static_cast<uint64_t>(n1) * n2, m);
  const auto p = points(SamplerKind::stratified, seed, 77, replicate, m);
  std::vector<int> hits(m, 0);
  // Offsets are recovered as u * n - cell; each coordinate is within 1 float ulp (<= 2^-24) of the
  // exact (cell + x) / n, so two recovered offsets differ by at most 2 * n * 2^-24.
  const double off1 = static_cast<double>(p[0].x) * n1, off2 = static_cast<double>(p[0].y) * n2;
  const double tol1 = n1 * 0x1p-23, tol2 = n2 * 0x1p-23;
  for (uint32_t k = 0; k < m; ++k) {
    const uint32_t i = cell(p[k].x, n1), j = cell(p[k].y, n2);
    ASSERT_LT(i, n1);
    ASSERT_LT(j, n2);
    EXPECT_EQ(static_cast<uint64_t>(i) * n2 + j, k) << "m=" << m << ": row-major order";
    ++hits[static_cast<size_t>(i) * n2 + j];
    EXPECT_NEAR(static_cast<double>(p[k].x) * n1 - i, off1, tol1) << "m=" << m << " k=" << k;
    EXPECT_NEAR(static_cast<double>(p[k].y) * n2 - j, off2, tol2) << "m=" << m << " k=" << k;
  }
  for (uint32_t c = 0; c < m; ++c) ASSERT_EQ(hits[c], 1) << "m=" << m << " cell " << c;
}

TEST(SamplerStratified, OnePointPerCellWithOneSharedOffset) {
  for (uint32_t m = 1; m <= 300; ++m) expect_systematic_grid(m, 5, 0);
  for (uint32_t m : {512u, 1024u, 2310u, 3000u, 4096u, 4099u /* prime: 1 x 4099 */, 16384u})
    for (uint32_t r = 0; r < 8; ++r) expect_systematic_grid(m, 1000 + r, r);
}

TEST(SamplerStratified, GridShapes) {
  EXPECT_EQ(expected_grid(32), std::make_pair(4u, 8u));
  EXPECT_EQ(expected_grid(256), std::make_pair(16u, 16u));
  EXPECT_EQ(expected_grid(12), std::make_pair(3u, 4u));
  EXPECT_EQ(expected_grid(13), std::make_pair(1u, 13u));
  // The sampler's shape: a 4 x 8 grid has 4 distinct x values and 8 distinct y values.
  const auto p = points(SamplerKind::stratified, 3, 4, 5, 32);
  std::vector<float> xs, ys;
  for (const auto& q : p) {
    if (std::find(xs.begin(), xs.end(), q.x) == xs.end()) xs.push_back(q.x);
    if (std::find(ys.begin(), ys.end(), q.y) == ys.end()) ys.push_back(q.y);
  }
  EXPECT_EQ(xs.size(), 4u);
  EXPECT_EQ(ys.size(), 8u);
}

TEST(SamplerStratified, OffsetsAreUniformAndIndependentAcrossReplicates) {
  // The offset (x1, x2) of replicate r is p[0] * (n1, n2) for m = 16 (4 x 4). Over R replicates the
  // offsets are i.i.d. U[0,1)^2: mean 1/2 (sd 1/sqrt(12 R)), E[x1 x2] = 1/4 (sd sqrt(7/144 / R)),
  // and an 8 x 8 histogram passes chi-square (63 dof; 130 is the p ~ 1e-6 quantile).
  constexpr int R = 20000;
  double sx = 0, sy = 0, sxy = 0;
  std::vector<int> hist(64, 0);
  for (uint32_t r = 0; r < R; ++r) {
    const auto p = points(SamplerKind::stratified, 9, 314, r, 16);
    const double x = p[0].x * 4.0, y = p[0].y * 4.0;
    sx += x;
    sy += y;
    sxy += x * y;
    ++hist[static_cast<size_t>(std::floor(x * 8) * 8 + std::floor(y * 8))];
  }
  const double sd_mean = 1.0 / std::sqrt(12.0 * R), sd_prod = std::sqrt(7.0 / 144.0 / R);
  EXPECT_NEAR(sx / R, 0.5, 4 * sd_mean);
  EXPECT_NEAR(sy / R, 0.5, 4 * sd_mean);
  EXPECT_NEAR(sxy / R, 0.25, 4 * sd_prod);
  EXPECT_LT(chi_square(hist, R), 130.0);
}

// ---- sobol ----

// Sobol dimension 1 computed independently, in the natural (not bit-reversed) domain: direction
// numbers v_1 = 1/2, v_{k+1} = v_k xor (v_k / 2) (the recurrence m_k = 2 m_{k-1} xor m_{k-1} of the
// primitive polynomial x + 1, written for v_k = m_k / 2^k), point i = xor of v_k over the set bits.
uint32_t sobol_dim1_natural(uint32_t index) {
  uint32_t v = 0x80000000u, x = 0;
  for (int k = 0; k < 32; ++k, v ^= v >> 1)
    if ((index >> k) & 1u) x ^= v;
  return x;
}

TEST(SamplerSobol, UnscrambledPointsMatchTheDirectionNumbers) {
  // The first 8 points in natural index order (the familiar Gray-code-order list (1/2, 1/2),
  // (3/4, 1/4), (1/4, 3/4), (3/8, 3/8), (7/8, 7/8), ... is these at indices 1, 3, 2, 6, 7, ...).
  const double x0[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double x1[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (uint32_t i = 0; i < 8; ++i) {
    const glm::uvec2 s = sobol_detail::sobol_bits(i);
    EXPECT_EQ(s.x * 0x1p-32, x0[i]) << i;
    EXPECT_EQ(s.y * 0x1p-32, x1[i]) << i;
  }
  SplitMix64 rng(7);
  for (uint32_t t = 0; t < 20000; ++t) {
    const uint32_t i = t < 10000 ? t : static_cast<uint32_t>(rng.next());
    const glm::uvec2 s = sobol_detail::sobol_bits(i);
    uint32_t vdc = 0;  // van der Corput: the bits of i mirrored about the binary point
    for (int k = 0; k < 32; ++k) vdc |= ((i >> k) & 1u) << (31 - k);
    ASSERT_EQ(s.x, vdc) << i;
    ASSERT_EQ(s.y, sobol_dim1_natural(i)) << i;
  }
}

TEST(SamplerSobol, OwenScrambleIsNested) {
  // Two values that share their top L bits and differ at bit L (from the top) must share their top
  // L bits after scrambling, and still differ at bit L: each digit is flipped by a function of the
  // seed and the digits above it only (Owen's nested uniform scramble).
  SplitMix64 rng(11);
  for (int t = 0; t < 200000; ++t) {
    const auto seed = static_cast<uint32_t>(rng.next());
    const auto x = static_cast<uint32_t>(rng.next());
    const int L = static_cast<int>(rng.below(32));
    const uint32_t flip = 0x80000000u >> L;
    const uint32_t low = flip - 1u;  // bits below L
    const uint32_t y = ((x ^ flip) & ~low) | (static_cast<uint32_t>(rng.next()) & low);
    const uint32_t sx = sobol_detail::owen_scramble(x, seed);
    const uint32_t sy = sobol_detail::owen_scramble(y, seed);
    const uint32_t top = L == 0 ? 0u : ~((flip << 1) - 1u);  // the top L bits
    ASSERT_EQ(sx & top, sy & top) << "L=" << L;
    ASSERT_NE(sx & flip, sy & flip) << "L=" << L;
  }
}

TEST(SamplerSobol, OwenScrambleFlipsEachLeadingDigitForHalfTheSeeds) {
  // Over many seeds, each of the top 8 digits of scramble(x) is 1 with probability 1/2
  // (sd 0.5 / sqrt(S)), for several x: the scramble randomises every level of the tree.
  constexpr int S = 40000;
  for (uint32_t x : {0u, 0xFFFFFFFFu, 0x12345678u, 0x80000000u}) {
    std::vector<int> ones(8, 0);
    SplitMix64 rng(x + 1);
    for (int s = 0; s < S; ++s) {
      const uint32_t v = sobol_detail::owen_scramble(x, static_cast<uint32_t>(rng.next()));
      for (int d = 0; d < 8; ++d) ones[d] += (v >> (31 - d)) & 1u;
    }
    for (int d = 0; d < 8; ++d)
      EXPECT_NEAR(ones[d] / static_cast<double>(S), 0.5, 4 * 0.5 / std::sqrt(S))
          << "x=" << x << " digit " << d;
  }
}

// Exactly one point in every elementary interval [a 2^-i, (a+1) 2^-i) x [b 2^-j, (b+1) 2^-j) with
// i + j = log2 m: the (0, log2 m, 2)-net property in base 2.
void expect_net(const glm::vec2* p, uint32_t m, const std::string& what) {
  const int k = std::countr_zero(m);
  ASSERT_EQ(1u << k, m);
  std::vector<int> hits(m);
  for (int i = 0; i <= k; ++i) {
    const int j = k - i;
    std::fill(hits.begin(), hits.end(), 0);
    for (uint32_t q = 0; q < m; ++q) ++hits[(cell(p[q].x, 1u << i) << j) | cell(p[q].y, 1u << j)];
    for (uint32_t c = 0; c < m; ++c)
      ASSERT_EQ(hits[c], 1) << what << ": m=" << m << " shape 2^" << i << " x 2^" << j << " cell "
                            << c;
  }
}

TEST(SamplerSobol, EveryReplicateOfPowerOfTwoSizeIsANet) {
  for (uint32_t k = 0; k <= 14; ++k) {
    const uint32_t m = 1u << k;
    for (uint64_t seed : {1ull, 2ull, 0xDEADBEEFull})
      for (uint32_t r = 0; r < 8; ++r) {
        const auto p = points(SamplerKind::sobol, seed, seed * 31 + r, r, m);
        expect_net(p.data(), m, "seed " + std::to_string(seed) + " replicate " + std::to_string(r));
      }
  }
}

TEST(SamplerSobol, PointsArePrefixesOfOneSequence) {
  // m = 3000 is not a power of two; its first 2048 points are the 2048-point replicate (a net).
  const auto big = points(SamplerKind::sobol, 5, 6, 7, 3000);
  const auto small = points(SamplerKind::sobol, 5, 6, 7, 2048);
  EXPECT_TRUE(std::memcmp(big.data(), small.data(), 2048 * sizeof(glm::vec2)) == 0);
  expect_net(big.data(), 2048, "prefix of 3000");
  expect_net(big.data() + 1024, 1024, "second block of 1024");  // aligned blocks are nets too
}

// A sequence that advances frame by frame (rtao): calls with first = 0, 4, 8, ... are the blocks
// of one call from 0, bit for bit, so 64 frames of 4 rays are that pixel's 256-point net.
TEST(SamplerSobol, StartingAtFirstContinuesTheSameSequence) {
  const auto whole = points(SamplerKind::sobol, 5, 6, 7, 256);
  std::vector<glm::vec2> frames(256);
  for (uint32_t f = 0; f < 64; ++f)
    sample_square(SamplerKind::sobol, 5, 6, 7, 4, frames.data() + 4 * f, 4 * f);
  EXPECT_TRUE(std::memcmp(whole.data(), frames.data(), 256 * sizeof(glm::vec2)) == 0);
  expect_net(frames.data(), 256, "64 frames of 4");
  // The other samplers draw afresh for another first.
  for (SamplerKind kind : {SamplerKind::random, SamplerKind::stratified}) {
    std::vector<glm::vec2> a(4), b(4);
    sample_square(kind, 5, 6, 7, 4, a.data(), 0);
    sample_square(kind, 5, 6, 7, 4, b.data(), 4);
    EXPECT_NE(std::memcmp(a.data(), b.data(), 4 * sizeof(glm::vec2)), 0);
  }
}
TEST(SamplerSobol, EachPointIsUniformAcrossReplicates) {
  // Under Owen scrambling every single point is U[0,1)^2 with independent coordinates. Over R
  // replicates, for several fixed indices: mean 1/2 (sd 1/sqrt(12 R)), E[x y] = 1/4
  // (sd sqrt(7/144 / R)), 8 x 8 histogram chi-square < 130 (63 dof, p ~ 1e-6).
  constexpr int R = 20000;
  constexpr uint32_t m = 256;
  const uint32_t indices[] = {0, 1, 37, 128, 255};
  std::vector<double> sx(5), sy(5), sxy(5);
  std::vector<std::vector<int>> hist(5, std::vector<int>(64, 0));
  // The mean over all m points of a replicate: a scrambled (0, k, 2)-net in base 2 has variance at
  // most e sigma^2 / m (Owen 1997, base b >= dimension), sigma^2 = 1/12, so over R replicates the
  // grand mean has sd <= sqrt(e / (12 m R)).
  double grand = 0;
  std::vector<glm::vec2> p(m);
  for (uint32_t r = 0; r < R; ++r) {
    sample_square(SamplerKind::sobol, 123, 456, r, m, p.data());
    for (int t = 0; t < 5; ++t) {
      const glm::vec2 q = p[indices[t]];
      sx[t] += q.x;
      sy[t] += q.y;
      sxy[t] += static_cast<double>(q.x) * q.y;
      ++hist[t][cell(q.x, 8) * 8 + cell(q.y, 8)];
    }
    for (const auto& q : p) grand += q.x + q.y;
  }
  const double sd_mean = 1.0 / std::sqrt(12.0 * R), sd_prod = std::sqrt(7.0 / 144.0 / R);
  for (int t = 0; t < 5; ++t) {
    EXPECT_NEAR(sx[t] / R, 0.5, 4 * sd_mean) << "index " << indices[t];
    EXPECT_NEAR(sy[t] / R, 0.5, 4 * sd_mean) << "index " << indices[t];
    EXPECT_NEAR(sxy[t] / R, 0.25, 4 * sd_prod) << "index " << indices[t];
    EXPECT_LT(chi_square(hist[t], R), 130.0) << "index " << indices[t];
  }
  EXPECT_NEAR(grand / (2.0 * m * R), 0.5, 4 * std::sqrt(std::exp(1.0) / (12.0 * m * R)));
}

TEST(SamplerSobol, ReplicatesOfDifferentPixelsAreIndependent) {
  // Correlation of point 0's x between neighbouring pixels over P pixels: sd 1/sqrt(P).
  constexpr int P = 20000;
  double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
  for (uint64_t px = 0; px < P; ++px) {
    const double a = points(SamplerKind::sobol, 8, px, 0, 4)[0].x;
    const double b = points(SamplerKind::sobol, 8, px + 1, 0, 4)[0].x;
    sa += a, sb += b, sab += a * b, saa += a * a, sbb += b * b;
  }
  const double cov = sab / P - (sa / P) * (sb / P);
  const double corr = cov / std::sqrt((saa / P - sa * sa / P / P) * (sbb / P - sb * sb / P / P));
  EXPECT_NEAR(corr, 0.0, 4.0 / std::sqrt(P));
}

// ---- random ----

TEST(SamplerRandom, PointsAreUniform) {
  // N i.i.d. points: mean 1/2 (sd 1/sqrt(12 N)), E[x y] = 1/4 (sd sqrt(7/144 / N)), 16 x 16
  // histogram chi-square < 350 (255 dof; mean 255, sd 22.6; 350 is p ~ 1e-6).
  constexpr uint32_t N = 1u << 20;
  const auto p = points(SamplerKind::random, 17, 18, 0, N);
  double sx = 0, sy = 0, sxy = 0;
  std::vector<int> hist(256, 0);
  for (const auto& q : p) {
    sx += q.x;
    sy += q.y;
    sxy += static_cast<double>(q.x) * q.y;
    ++hist[cell(q.x, 16) * 16 + cell(q.y, 16)];
  }
  EXPECT_NEAR(sx / N, 0.5, 4 / std::sqrt(12.0 * N));
  EXPECT_NEAR(sy / N, 0.5, 4 / std::sqrt(12.0 * N));
  EXPECT_NEAR(sxy / N, 0.25, 4 * std::sqrt(7.0 / 144.0 / N));
  EXPECT_LT(chi_square(hist, N), 350.0);
}

// ---- variance and bias of the replicate means ----

// R replicate means of f over m points of `kind`.
template <class F>
std::vector<double> replicate_means(SamplerKind kind, uint32_t m, int R, F f) {
  std::vector<double> means(R);
  std::vector<glm::vec2> p(m);
  for (int r = 0; r < R; ++r) {
    sample_square(kind, 2024, 99, static_cast<uint32_t>(r), m, p.data());
    double s = 0;
    for (const auto& q : p) s += f(q);
    means[r] = s / m;
  }
  return means;
}

double product(glm::vec2 u) {
  return static_cast<double>(u.x) * u.y;
}
// The indicator of the disk of radius 0.4 centred in the square (area 0.16 pi).
double in_disk(glm::vec2 u) {
  const double dx = u.x - 0.5, dy = u.y - 0.5;
  return dx * dx + dy * dy < 0.16 ? 1.0 : 0.0;
}

// With R = 1000 replicates, a variance estimate of (near-Gaussian) replicate means has relative sd
// sqrt(2 / (R - 1)) = 4.5%, so 4 sd is +-18% (conservative for the flat-tailed systematic means).
constexpr int kReplicates = 1000;
const double kVarTol = 4 * std::sqrt(2.0 / (kReplicates - 1));

TEST(SamplerVariance, SmoothIntegrand) {
  // f = x y over m = 256 points: integral 1/4, per-point variance 1/9 - 1/16 = 7/144.
  constexpr uint32_t m = 256;
  const double random_var = 7.0 / 144.0 / m;
  const Moments rnd = moments(replicate_means(SamplerKind::random, m, kReplicates, product));
  const Moments sys = moments(replicate_means(SamplerKind::stratified, m, kReplicates, product));
  const Moments sob = moments(replicate_means(SamplerKind::sobol, m, kReplicates, product));
  EXPECT_NEAR(rnd.var / random_var, 1.0, kVarTol);
  // Systematic 16 x 16 grid: the mean is (1/2 + a)(1/2 + b), a = (x1 - 1/2)/16, b likewise, so its
  // variance is (Va + Vb)/4 + Va Vb with Va = Vb = 1/(12 * 16^2): a check of the one shared offset.
  const double va = 1.0 / (12.0 * 256.0);
  EXPECT_NEAR(sys.var / (va / 2 + va * va), 1.0, kVarTol);
  // Owen-scrambled nets converge like O(m^-3 log m) on smooth integrands: orders of magnitude below
  // random; 10x is a loose floor (the estimate itself is good to +-18%).
  EXPECT_LT(sob.var, random_var / 10) << "sobol variance " << sob.var << " vs " << random_var;
  for (const Moments& mo : {rnd, sys, sob})  // unbiased: 4 sd of the mean of R replicates
    EXPECT_NEAR(mo.mean, 0.25, 4 * std::sqrt(mo.var / kReplicates) + 1e-12);
}

TEST(SamplerVariance, DiscontinuousIntegrand) {
  // The disk indicator over m = 256 points: integral p = 0.16 pi, per-point variance p (1 - p).
  // For a set with a smooth boundary the scrambled-net variance is O(m^-3/2) against O(m^-1) for
  // random (He & Owen 2015): about 1/sqrt(256) = 1/16 times a constant; 1/3 is a loose bound.
  constexpr uint32_t m = 256;
  const double p = 0.16 * kPi, random_var = p * (1 - p) / m;
  const Moments rnd = moments(replicate_means(SamplerKind::random, m, kReplicates, in_disk));
  const Moments sys = moments(replicate_means(SamplerKind::stratified, m, kReplicates, in_disk));
  const Moments sob = moments(replicate_means(SamplerKind::sobol, m, kReplicates, in_disk));
  EXPECT_NEAR(rnd.var / random_var, 1.0, kVarTol);
  EXPECT_LT(sob.var, random_var / 3) << "sobol variance " << sob.var << " vs " << random_var;
  EXPECT_LT(sys.var, random_var / 3) << "stratified variance " << sys.var << " vs " << random_var;
  for (const Moments& mo : {rnd, sys, sob})
    EXPECT_NEAR(mo.mean, p, 4 * std::sqrt(mo.var / kReplicates) + 1e-12);
}

TEST(SamplerVariance, UnbiasedForSizesThatAreNotPowersOfTwo) {
  // The reference uses m = spp / 8, often not a power of two (e.g. spp 100 -> m 12 or 25).
  for (uint32_t m : {3u, 12u, 25u, 200u}) {
    for (SamplerKind k : kAllKinds) {
      const Moments a = moments(replicate_means(k, m, 4000, product));
      EXPECT_NEAR(a.mean, 0.25, 4 * std::sqrt(a.var / 4000)) << sampler_name(k) << " m=" << m;
      const Moments b = moments(replicate_means(k, m, 4000, in_disk));
      EXPECT_NEAR(b.mean, 0.16 * kPi, 4 * std::sqrt(b.var / 4000)) << sampler_name(k) << " m=" << m;
    }
  }
}

// ---- hemisphere maps ----

TEST(SamplerHemisphereMaps, UnitLengthAndUpperHemisphere) {
  std::vector<float> us;
  for (int i = 0; i <= 256; ++i) us.push_back(i / 256.0f);
  us.back() = kOneMinus;
  for (float e : {0x1p-24f, 0.5f - 0x1p-24f, 0.5f + 0x1p-23f, 0.25f, 0.75f}) us.push_back(e);
  for (float a : us)
    for (float b : us)
      for (const glm::vec3 w :
           {square_to_cosine_hemisphere({a, b}), square_to_uniform_hemisphere({a, b})}) {
        ASSERT_TRUE(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z));
        ASSERT_NEAR(glm::length(w), 1.0f, 1e-6f) << a << ", " << b;
        ASSERT_GE(w.z, 0.0f) << a << ", " << b;
      }
  EXPECT_EQ(square_to_cosine_hemisphere({0.5f, 0.5f}), glm::vec3(0, 0, 1));
  EXPECT_EQ(square_to_uniform_hemisphere({0.0f, 0.3f}), glm::vec3(0, 0, 1));
}

// The batch maps vectorise (the cosine one has no early return): the reference's directions must
// stay the single-point maps' bits, the centre of the square and the edges included.
TEST(SamplerHemisphereMaps, BatchMapsAreTheSinglePointMapsBitForBit) {
  std::vector<glm::vec2> points;
  SplitMix64 rng(12345);
  for (int i = 0; i < 4093; ++i) points.emplace_back(rng.uniform_float(), rng.uniform_float());
  for (float a : {0.0f, 0.5f, kOneMinus, 0.5f + 0x1p-24f})
    for (float b : {0.0f, 0.5f, kOneMinus, 0.5f - 0x1p-24f}) points.emplace_back(a, b);
  const size_t n = points.size();
  std::vector<float> cx(n), cy(n), cz(n), ux(n), uy(n), uz(n);
  square_to_cosine_hemisphere(points.data(), static_cast<uint32_t>(n), cx.data(), cy.data(),
                              cz.data());
  square_to_uniform_hemisphere(points.data(), static_cast<uint32_t>(n), ux.data(), uy.data(),
                               uz.data());
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 c = square_to_cosine_hemisphere(points[i]);
    const glm::vec3 u = square_to_uniform_hemisphere(points[i]);
    const glm::vec3 cosine(cx[i], cy[i], cz[i]), uniform(ux[i], uy[i], uz[i]);
    ASSERT_EQ(std::memcmp(&c, &cosine, sizeof c), 0) << points[i].x << ", " << points[i].y;
    ASSERT_EQ(std::memcmp(&u, &uniform, sizeof u), 0) << points[i].x << ", " << points[i].y;
  }
}

TEST(SamplerHemisphereMaps, ConcentricDiskKeepsStrataCompact) {
  // Shirley & Chiu: the square [0,1)^2 maps to the disk (the directions' xy) so that the square of
  // "radius" r = max(|2u.x - 1|, |2u.y - 1|) becomes the circle of radius r, and the map is
  // Lipschitz: in a wedge, (a, b) -> a (cos(pi b / 4a), sin(pi b / 4a)) has Jacobian columns of
  // norm
  // <= 1 + pi/4 and pi/4, so |d disk| <= 2 (1 + pi/2) |du|_inf (the 2 from u -> a = 2u - 1).
  SplitMix64 rng(3);
  const double lipschitz = 2.0 * (1.0 + kPi / 2.0);
  for (int t = 0; t < 200000; ++t) {
    const glm::vec2 u(rng.uniform_float(), rng.uniform_float());
    const glm::vec3 w = square_to_cosine_hemisphere(u);
    const double r = std::max(std::abs(2.0 * u.x - 1.0), std::abs(2.0 * u.y - 1.0));
    ASSERT_NEAR(std::hypot(w.x, w.y), r, 1e-6);
    const float h = 1e-3f;
    const glm::vec2 v =
        glm::clamp(u + glm::vec2(rng.uniform(-h, h), rng.uniform(-h, h)), 0.0f, kOneMinus);
    const glm::vec3 w2 = square_to_cosine_hemisphere(v);
    const double du = std::max(std::abs(v.x - u.x), std::abs(v.y - u.y));
    ASSERT_LE(std::hypot(w2.x - w.x, w2.y - w.y), lipschitz * du + 1e-6) << u.x << ", " << u.y;
  }
}

// Monte-Carlo estimates of E[g(w)] under a map with N i.i.d. points, checked against the exact
// value with tolerance 4 sigma / sqrt(N), sigma^2 the exact variance of g.
struct Expectation {
  const char* what;
  double (*g)(const glm::vec3&);
  double mean, var;
};

void check_expectations(glm::vec3 (*map)(glm::vec2), const std::vector<Expectation>& checks) {
  constexpr uint32_t N = 1u << 20;
  const auto u = points(SamplerKind::random, 31337, 0, 0, N);
  std::vector<double> sums(checks.size(), 0.0);
  for (const auto& q : u) {
    const glm::vec3 w = map(q);
    for (size_t c = 0; c < checks.size(); ++c) sums[c] += checks[c].g(w);
  }
  for (size_t c = 0; c < checks.size(); ++c)
    EXPECT_NEAR(sums[c] / N, checks[c].mean, 4 * std::sqrt(checks[c].var / N)) << checks[c].what;
}

template <int kDegrees>
double theta_below(const glm::vec3& w) {
  return w.z > std::cos(kDegrees * kPi / 180.0) ? 1.0 : 0.0;
}
double cos_theta(const glm::vec3& w) {
  return w.z;
}
double cos2_theta(const glm::vec3& w) {
  return static_cast<double>(w.z) * w.z;
}
double first_quadrant(const glm::vec3& w) {
  return w.x > 0 && w.y > 0 ? 1.0 : 0.0;
}
double bernoulli_var(double p) {
  return p * (1 - p);
}
double sin2(double deg) {
  return std::pow(std::sin(deg * kPi / 180.0), 2);
}
double one_minus_cos(double deg) {
  return 1.0 - std::cos(deg * kPi / 180.0);
}

TEST(SamplerHemisphereMaps, CosineMapHasPdfCosThetaOverPi) {
  // Under pdf cos/pi: E[cos] = 2/3, E[cos^2] = 1/2, E[cos^4] = 1/3; P(theta < a) = sin^2 a.
  check_expectations(square_to_cosine_hemisphere,
                     {{"E[cos]", cos_theta, 2.0 / 3.0, 0.5 - 4.0 / 9.0},
                      {"E[cos^2]", cos2_theta, 0.5, 1.0 / 3.0 - 0.25},
                      {"P(theta<20)", theta_below<20>, sin2(20), bernoulli_var(sin2(20))},
                      {"P(theta<45)", theta_below<45>, sin2(45), bernoulli_var(sin2(45))},
                      {"P(theta<70)", theta_below<70>, sin2(70), bernoulli_var(sin2(70))},
                      {"P(quadrant 1)", first_quadrant, 0.25, bernoulli_var(0.25)}});
}

TEST(SamplerHemisphereMaps, UniformMapHasPdfOneOverTwoPi) {
  // Under pdf 1/(2 pi): E[cos] = 1/2, E[cos^2] = 1/3, E[cos^4] = 1/5; P(theta < a) = 1 - cos a.
  check_expectations(
      square_to_uniform_hemisphere,
      {{"E[cos]", cos_theta, 0.5, 1.0 / 3.0 - 0.25},
       {"E[cos^2]", cos2_theta, 1.0 / 3.0, 0.2 - 1.0 / 9.0},
       {"P(theta<20)", theta_below<20>, one_minus_cos(20), bernoulli_var(one_minus_cos(20))},
       {"P(theta<45)", theta_below<45>, one_minus_cos(45), bernoulli_var(one_minus_cos(45))},
       {"P(theta<70)", theta_below<70>, one_minus_cos(70), bernoulli_var(one_minus_cos(70))},
       {"P(quadrant 1)", first_quadrant, 0.25, bernoulli_var(0.25)}});
}

// ---- frames ----

void expect_orthonormal(const glm::vec3& n) {
  const Frame f = make_frame(n);
  const float tol = 2e-6f;
  ASSERT_EQ(f.n, n);
  ASSERT_NEAR(glm::length(f.t), 1.0f, tol) << n.x << " " << n.y << " " << n.z;
  ASSERT_NEAR(glm::length(f.b), 1.0f, tol) << n.x << " " << n.y << " " << n.z;
  ASSERT_NEAR(glm::dot(f.t, f.b), 0.0f, tol) << n.x << " " << n.y << " " << n.z;
  ASSERT_NEAR(glm::dot(f.t, n), 0.0f, tol) << n.x << " " << n.y << " " << n.z;
  ASSERT_NEAR(glm::dot(f.b, n), 0.0f, tol) << n.x << " " << n.y << " " << n.z;
  const glm::vec3 c = glm::cross(f.t, f.b);  // right-handed: t x b = n
  ASSERT_NEAR(glm::length(c - n), 0.0f, 2 * tol) << n.x << " " << n.y << " " << n.z;
  ASSERT_EQ(f.to_world({0, 0, 1}), n);
  const glm::vec3 w = f.to_world(glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)));
  ASSERT_NEAR(glm::length(w), 1.0f, 2 * tol);
}

TEST(SamplerFrame, OrthonormalRightHandedForAllNormals) {
  for (const glm::vec3 n :
       {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
        glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, -0.0f), glm::vec3(1, 0, -0.0f)})
    if (glm::length(n) > 0.5f) expect_orthonormal(n);
  // Near -Z, where the unrevised Frisvad construction breaks down.
  for (float e : {1e-3f, 1e-5f, 1e-7f, 1e-9f}) {
    expect_orthonormal(glm::normalize(glm::vec3(e, 0, -1)));
    expect_orthonormal(glm::normalize(glm::vec3(-e, e, -1)));
    expect_orthonormal(glm::normalize(glm::vec3(e, e, 1)));
  }
  SplitMix64 rng(99);  // uniform on the sphere
  for (int t = 0; t < 200000; ++t) {
    const float z = rng.uniform(-1.0f, 1.0f),
                phi = rng.uniform(0.0f, 2.0f * static_cast<float>(kPi));
    const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    expect_orthonormal(glm::normalize(glm::vec3(s * std::cos(phi), s * std::sin(phi), z)));
  }
}

}  // namespace
}  // namespace aoeval
