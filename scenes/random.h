// Deterministic, platform-independent random numbers. The standard library's distributions are
// implementation-defined, so generators and samplers use these instead: same seed, same bits.
#pragma once

#include <cstdint>

namespace aoeval {

// SplitMix64 (Steele, Lea, Flood 2014): a fast 64-bit generator with good statistical quality,
// also used to derive independent streams from (seed, index) pairs.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 24 bits, exactly representable as float.
  float uniform_float() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
  // Uniform in [0, 1) with 53 bits.
  double uniform_double() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform_float(); }
  // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; bias < 2^-32 for n < 2^32).
  uint32_t below(uint32_t n) {
    return static_cast<uint32_t>(((next() >> 32) * static_cast<uint64_t>(n)) >> 32);
  }

 private:
  uint64_t state_;
};

// A well-mixed 64-bit key from several integers: independent streams per (seed, pixel, ...).
inline uint64_t mix_seed(uint64_t a, uint64_t b, uint64_t c = 0) {
  SplitMix64 g(a ^ 0x6A09E667F3BCC909ull);
  uint64_t h = g.next() ^ b;
  SplitMix64 g2(h);
  h = g2.next() ^ c;
  SplitMix64 g3(h);
  return g3.next();
}

}  // namespace aoeval
