// Hemisphere samplers of the Embree reference: random, stratified (the systematic sampling of
// Méndez et al. 2003, §4.2) and Owen-scrambled Sobol (hash-based nested uniform scrambling after
// Burley 2020) point sets in the unit square; the cosine map (Malley's method on the concentric
// disk of Shirley & Chiu 1997) and the uniform map onto the hemisphere; and the orthonormal frame
// of Duff et al. 2017. See samplers.h.
#include "sampling/samplers.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "base/errors.h"
#include "scenes/random.h"

namespace aoeval {

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kOneMinus = 0x1.fffffep-1f;  // the largest float below 1

// Tags that keep the three samplers' streams apart for the same (seed, pixel, replicate).
uint64_t stream_key(SamplerKind kind, uint64_t seed, uint64_t pixel, uint32_t replicate) {
  return mix_seed(seed, pixel, (static_cast<uint64_t>(kind) + 1) << 32 | replicate);
}

// ---- stratified ----

// n1 = the largest divisor of m with n1 <= sqrt(m).
uint32_t grid_rows(uint32_t m) {
  auto r = static_cast<uint32_t>(std::sqrt(static_cast<double>(m)));
  while (static_cast<uint64_t>(r) * r > m) --r;
  while (static_cast<uint64_t>(r + 1) * (r + 1) <= m) ++r;
  while (m % r != 0) --r;
  return r;
}

// (i + x) / n as a float that lies in the cell [i / n, (i + 1) / n) exactly (for n <= 2^24),
// despite the roundings of the double product and of the conversion to float. `inv_n` = 1 / n, x in
// [0, 1).
float cell_coordinate(uint32_t i, double x, uint32_t n, double inv_n) {
  float f = static_cast<float>((static_cast<double>(i) + x) * inv_n);
  // double(f) * n is exact for n < 2^29 (24 + 29 bits), so these are exact cell tests.
  const double scaled = static_cast<double>(f) * static_cast<double>(n);
  if (scaled >= static_cast<double>(i) + 1.0)
    f = std::bit_cast<float>(std::bit_cast<uint32_t>(f) - 1u);  // f > 0 here: one float down
  else if (scaled < static_cast<double>(i))
    f = std::bit_cast<float>(std::bit_cast<uint32_t>(f) + 1u);  // f >= 0 here: one float up
  return f < kOneMinus ? f : kOneMinus;
}

void sample_stratified(uint64_t key, uint32_t m, glm::vec2* out) {
  const uint32_t n1 = grid_rows(m), n2 = m / n1;
  SplitMix64 rng(key);
  // The one offset shared by all cells (Méndez et al. 2003, §4.2).
  const double x1 = rng.uniform_double(), x2 = rng.uniform_double();
  const double inv1 = 1.0 / n1, inv2 = 1.0 / n2;
  // Row 0 computes the n2 column coordinates; the other rows reuse them from `out`.
  const float u0 = cell_coordinate(0, x1, n1, inv1);
  for (uint32_t j = 0; j < n2; ++j) out[j] = glm::vec2(u0, cell_coordinate(j, x2, n2, inv2));
  for (uint32_t i = 1; i < n1; ++i) {
    const float ui = cell_coordinate(i, x1, n1, inv1);
    glm::vec2* row = out + static_cast<size_t>(i) * n2;
    for (uint32_t j = 0; j < n2; ++j) row[j] = glm::vec2(ui, out[j].y);
  }
}

// ---- sobol ----

uint32_t reverse_bits(uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x & 0x0F0F0F0Fu) << 4) | ((x >> 4) & 0x0F0F0F0Fu);
  x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
  x = ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
  return x;
}

// Direction numbers of Sobol dimension 1 (primitive polynomial x + 1, degree s = 1, m_1 = 1): the
// recurrence m_k = 2 m_{k-1} xor m_{k-1} gives m_k = row k-1 of Pascal's triangle mod 2 (1, 3, 5,
// 15, 17, 51, ...), and v_k = m_k / 2^k. In the bit-reversed domain the generator column of index
// bit j is reverse_32(m_{j+1} << (31 - j)) = m_{j+1} (the row is a palindrome), so kDim1[j] =
// m_{j+1}.
constexpr std::array<uint32_t, 32> make_dim1_columns() {
  std::array<uint32_t, 32> m{};
  m[0] = 1;
  for (int j = 1; j < 32; ++j) m[j] = m[j - 1] ^ (m[j - 1] << 1);
  return m;
}
constexpr std::array<uint32_t, 32> kDim1 = make_dim1_columns();

// kDim1Step[t] = kDim1[0] ^ ... ^ kDim1[t]: going from index i to i + 1 flips index bits 0..t,
// t = ctz(i + 1), so the reversed dimension-1 value changes by kDim1Step[t].
constexpr std::array<uint32_t, 32> make_dim1_steps() {
  std::array<uint32_t, 32> s{};
  uint32_t acc = 0;
  for (int t = 0; t < 32; ++t) s[t] = acc ^= kDim1[t];
  return s;
}
constexpr std::array<uint32_t, 32> kDim1Step = make_dim1_steps();

// The Laine-Karras-style permutation of a bit-reversed value (Burley 2020, §3), with the better
// mixing constants of N. Vegdahl (2021). Every step (add, multiply by odd, xor with a multiple by
// an even constant) makes output bit k depend only on input bits <= k and is a bijection modulo
// 2^k: in the reversed domain that is exactly a nested (Owen) scramble, so nets stay nets.
uint32_t owen_permute_reversed(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// The top 24 bits as a float in [0, 1): exact (a 24-bit integer times a power of two).
float fraction24(uint32_t x) {
  return static_cast<float>(x >> 8) * 0x1p-24f;
}

// The reversed dimension-1 value of index i: the xor of the generator columns of its set bits.
uint32_t dim1_reversed(uint32_t i) {
  uint32_t y = 0;
  for (uint32_t j = 0; i != 0; i >>= 1, ++j)
    if (i & 1u) y ^= kDim1[j];
  return y;
}

// Points first .. first + m - 1 of the scrambled sequence (the scramble depends on the key only).
void sample_sobol(uint64_t key, uint32_t first, uint32_t m, glm::vec2* out) {
  SplitMix64 rng(key);
  const uint64_t seeds = rng.next();  // one independent scramble per dimension
  const auto seed0 = static_cast<uint32_t>(seeds), seed1 = static_cast<uint32_t>(seeds >> 32);
  // Reversed dimension-1 value of index i; dimension 0 reversed is i itself.
  uint32_t dim1 = first == 0 ? 0u : dim1_reversed(first);
  for (uint32_t n = 0; n < m; ++n) {
    const uint32_t i = first + n;
    const uint32_t x = reverse_bits(owen_permute_reversed(i, seed0));
    const uint32_t y = reverse_bits(owen_permute_reversed(dim1, seed1));
    out[n] = glm::vec2(fraction24(x), fraction24(y));  // 24 bits: exact floats in [0, 1)
    if (i + 1 != 0) dim1 ^= kDim1Step[std::countr_zero(i + 1)];
  }
}

// ---- random ----

void sample_random(uint64_t key, uint32_t m, glm::vec2* out) {
  SplitMix64 rng(key);
  for (uint32_t i = 0; i < m; ++i) {
    const float x = rng.uniform_float();
    out[i] = glm::vec2(x, rng.uniform_float());
  }
}

}  // namespace

SamplerKind parse_sampler(const std::string& name) {
  if (name == "random") return SamplerKind::random;
  if (name == "stratified") return SamplerKind::stratified;
  if (name == "sobol") return SamplerKind::sobol;
  throw InputError("--sampler: unknown sampler '" + name +
                   "' (choices: random, stratified, sobol)");
}

const char* sampler_name(SamplerKind kind) {
  switch (kind) {
    case SamplerKind::random:
      return "random";
    case SamplerKind::stratified:
      return "stratified";
    case SamplerKind::sobol:
      return "sobol";
  }
  return "unknown";
}

void sample_square(SamplerKind kind, uint64_t seed, uint64_t pixel, uint32_t replicate, uint32_t m,
                   glm::vec2* out, uint32_t first) {
  if (m == 0) return;
  // Sobol continues one scrambled sequence from `first`; the others draw afresh for each first.
  uint64_t key = stream_key(kind, seed, pixel, replicate);
  if (first != 0 && kind != SamplerKind::sobol) key = mix_seed(key, first);
  switch (kind) {
    case SamplerKind::random:
      sample_random(key, m, out);
      return;
    case SamplerKind::stratified:
      sample_stratified(key, m, out);
      return;
    case SamplerKind::sobol:
      sample_sobol(key, first, m, out);
      return;
  }
}

namespace {

// The cosine map of square_to_cosine_hemisphere without a branch, so that a loop of it
// vectorises: the centre of the square (a = b = 0) computes q = 0 / 0 = NaN and is replaced by +Z
// at the end. Vectorised lanes do the same operations in the same order (no contraction into FMA
// at this ISA level), so a batch gives the same bits as single points (samplers_test).
inline glm::vec3 concentric_cosine(glm::vec2 u) {
  // Shirley & Chiu 1997: the square [-1, 1]^2 onto the unit disk, concentric squares to circles.
  const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
  // Left/right wedges (|a| > |b|): r = a, phi = pi/4 b/a; top/bottom: r = b, phi = pi/2 - pi/4 a/b.
  // Written with selects and one division (the wedge is unpredictable from point to point).
  const bool wide = std::abs(a) > std::abs(b);
  const float r = wide ? a : b;
  const float q = (wide ? b : a) / r;
  // phi = (pi/4) q on the wide wedges, pi/2 - (pi/4) q on the others: both need only the sine
  // and cosine of x = (pi/4) q in [-pi/4, pi/4], where short Taylor polynomials are exact to
  // float precision (truncation < 2e-9). Faster than libm's sincosf, and the same bits on every
  // platform's libm.
  const float x = (kPi / 4.0f) * q, x2 = x * x;
  const float sin_x =
      x *
      (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
  const float cos_x =
      1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320))));
  const float cos_phi = wide ? cos_x : sin_x, sin_phi = wide ? sin_x : cos_x;
  const float x_disk = r * cos_phi, y_disk = r * sin_phi;
  // Malley's method: lifting a uniform disk point to the hemisphere gives pdf cos(theta) / pi.
  const float z = std::sqrt(std::max(0.0f, 1.0f - x_disk * x_disk - y_disk * y_disk));
  const bool centre = a == 0.0f && b == 0.0f;
  return centre ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(x_disk, y_disk, z);
}

}  // namespace

glm::vec3 square_to_cosine_hemisphere(glm::vec2 u) {
  return concentric_cosine(u);
}

glm::vec3 square_to_uniform_hemisphere(glm::vec2 u) {
  const float z = 1.0f - u.x;                                     // exact for u.x in [0, 1)
  const float s = std::sqrt(std::max(0.0f, u.x * (2.0f - u.x)));  // sin(theta), = sqrt(1 - z^2)
  const float phi = 2.0f * kPi * u.y;
  return glm::vec3(s * std::cos(phi), s * std::sin(phi), z);
}

void square_to_cosine_hemisphere(const glm::vec2* in, uint32_t m, float* x, float* y, float* z) {
  for (uint32_t i = 0; i < m; ++i) {
    const glm::vec3 w = concentric_cosine(in[i]);
    x[i] = w.x, y[i] = w.y, z[i] = w.z;
  }
}

void square_to_uniform_hemisphere(const glm::vec2* in, uint32_t m, float* x, float* y, float* z) {
  for (uint32_t i = 0; i < m; ++i) {
    const glm::vec3 w = square_to_uniform_hemisphere(in[i]);
    x[i] = w.x, y[i] = w.y, z[i] = w.z;
  }
}

Frame make_frame(const glm::vec3& n) {
  // Duff et al. 2017 (the revised Frisvad construction): no singularity at n = -Z; the basis
  // jumps only where n.z changes sign.
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  Frame f;
  f.t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  f.b = glm::vec3(b, sign + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}

namespace sobol_detail {

glm::uvec2 sobol_bits(uint32_t index) {
  return glm::uvec2(reverse_bits(index), reverse_bits(dim1_reversed(index)));
}

uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(owen_permute_reversed(reverse_bits(x), seed));
}

}  // namespace sobol_detail

}  // namespace aoeval
