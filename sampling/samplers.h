// Hemisphere samplers of the Embree reference: point sets in the unit square, their maps onto the
// hemisphere around +Z, and an orthonormal frame that carries them to world space.
//
// Point sets (sample_square), each replicate an independent randomisation:
//  - random: i.i.d. uniform points.
//  - stratified: the systematic sampling of Méndez, Sbert, Catà, "Ray-traced obscurances" (2003),
//    §4.2: an n1 x n2 grid of cells with ONE random offset (x1, x2) shared by every cell, point
//    (i, j) = ((i + x1) / n1, (j + x2) / n2); n1 is the largest divisor of m with n1 <= sqrt(m).
//  - sobol: the first two dimensions of the Sobol sequence (van der Corput, and the dimension of
//    primitive polynomial x + 1), Owen-scrambled (nested uniform scrambling) with the hash-based
//    method of Burley, "Practical Hash-based Owen Scrambling" (JCGT 2020), using the improved
//    Laine-Karras-style permutation of N. Vegdahl ("Building a Better LK Hash", 2021). The points
//    are the first m of the sequence, so for m = 2^k each replicate is a (0, k, 2)-net in base 2.
// Hemisphere maps: cosine-weighted by Malley's method over the concentric disk map of Shirley and
// Chiu, "A Low Distortion Map Between Disk and Square" (1997), so strata stay compact; uniform by
// (cos theta = 1 - u.x, phi = 2 pi u.y). Frames: Duff et al., "Building an Orthonormal Basis,
// Revisited" (JCGT 2017).
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace aoeval {

enum class SamplerKind { random, stratified, sobol };

// "random", "stratified" or "sobol"; anything else throws InputError naming --sampler and the
// choices.
SamplerKind parse_sampler(const std::string& name);
const char* sampler_name(SamplerKind kind);

// Fills out[0..m) with m points in [0, 1)^2: replicate `replicate` of pixel `pixel` under `seed`.
// Deterministic: depends only on (kind, seed, pixel, replicate, m), never on threads or call order;
// distinct (seed, pixel, replicate) give independent randomisations. Allocation-free.
// Sobol: the points are the first m of the scrambled sequence, so a replicate of m points is a
// prefix of the same replicate with more points (and for m = 2^k a (0, k, 2)-net). Stratified: the
// grid is n1 x n2 = m exactly (a prime m gives a 1 x m grid), the points in row-major order (i,
// then j).
// `first` > 0 continues the replicate: sobol gives points first .. first + m - 1 of the same
// scrambled sequence (so calls with first = 0, m, 2m, ... together are its first points: a
// sequence that advances frame by frame, rtao's), random and stratified an independent draw.
void sample_square(SamplerKind kind, uint64_t seed, uint64_t pixel, uint32_t replicate, uint32_t m,
                   glm::vec2* out, uint32_t first = 0);

// Unit direction in the local frame where +Z is the normal, z >= 0.
// Cosine-weighted: pdf cos(theta) / pi (Malley's method on the Shirley-Chiu concentric disk).
glm::vec3 square_to_cosine_hemisphere(glm::vec2 u);
// Uniform: pdf 1 / (2 pi), cos(theta) = 1 - u.x, phi = 2 pi u.y.
glm::vec3 square_to_uniform_hemisphere(glm::vec2 u);
// The same maps over m points at once (a loop the compiler can vectorise), into separate
// coordinate arrays: (x[i], y[i], z[i]) = map(in[i]), the same bits. Structure of arrays is the
// form the reference's tracer turns to world space and packs into Embree's ray packets.
void square_to_cosine_hemisphere(const glm::vec2* in, uint32_t m, float* x, float* y, float* z);
void square_to_uniform_hemisphere(const glm::vec2* in, uint32_t m, float* x, float* y, float* z);

// A right-handed orthonormal basis (t, b, n), t x b = n, around the unit vector n (Duff et al.
// 2017).
struct Frame {
  glm::vec3 t, b, n;
  // world = t * local.x + b * local.y + n * local.z
  glm::vec3 to_world(const glm::vec3& local) const {
    return t * local.x + b * local.y + n * local.z;
  }
};
Frame make_frame(const glm::vec3& n);

// Building blocks of the sobol sampler, exposed for the tests.
namespace sobol_detail {
// The unscrambled Sobol point `index` (dimensions 0 and 1) as 32-bit fixed-point fractions.
glm::uvec2 sobol_bits(uint32_t index);
// Base-2 nested uniform (Owen) scramble of a 32-bit fixed-point fraction: bit k (from the top) of
// the result is bit k of x flipped by a pseudo-random function of `seed` and the bits above it.
uint32_t owen_scramble(uint32_t x, uint32_t seed);
}  // namespace sobol_detail

}  // namespace aoeval
