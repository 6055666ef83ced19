// sphere-uniform: a ball of radius `radius` (centred at the origin) uniformly filled with `count`
// small, randomly oriented equilateral triangles of edge `triangle_size`.
//
// This is the configuration from which Hegeman et al. 2006 ("Approximate Ambient Occlusion For
// Trees", §3, Fig. 2) derive their visibility model: a sphere filled with small occluders, whose
// ambient visibility they approximate by exp(-alpha rho f V_cap) (eq. 4-6). Their model assumes the
// occluders are independent, uniformly placed and isotropically oriented, so here:
//   - centres are uniform in the ball (rejection sampling in the cube: exact, no transcendental
//     functions, so every platform draws the same bits);
//   - orientations are uniform rotations (a uniform normal plus a uniform in-plane direction, both
//     from rejection-sampled unit vectors);
//   - every triangle has the same size, so the occluder density is count / (4/3 pi r^3).
// Centres lie within `radius`, so every vertex lies within radius + triangle_size / sqrt(3).
// Facts: envelope (the ball), leaf_count, leaf_area (exact sum of the triangle areas), leaf
// density.

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include <cmath>
#include <glm/geometric.hpp>

#include "scenes/generators/generators.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Every draw is its own statement: the evaluation order of function arguments is unspecified (GCC
// goes right to left, Clang left to right), and the bits must not depend on the compiler.
// A uniform point in the unit ball.
glm::vec3 in_unit_ball(SplitMix64& rng) {
  for (;;) {
    const float x = rng.uniform(-1.0f, 1.0f);
    const float y = rng.uniform(-1.0f, 1.0f);
    const float z = rng.uniform(-1.0f, 1.0f);
    const glm::vec3 p(x, y, z);
    if (glm::dot(p, p) <= 1.0f) return p;
  }
}

// A uniform direction.
glm::vec3 unit_vector(SplitMix64& rng) {
  for (;;) {
    const float x = rng.uniform(-1.0f, 1.0f);
    const float y = rng.uniform(-1.0f, 1.0f);
    const float z = rng.uniform(-1.0f, 1.0f);
    const glm::vec3 p(x, y, z);
    const float d = glm::dot(p, p);
    if (d <= 1.0f && d > 1e-4f) return p / std::sqrt(d);
  }
}

// A uniform direction perpendicular to the unit vector n.
glm::vec3 perpendicular(SplitMix64& rng, glm::vec3 n) {
  for (;;) {
    glm::vec3 w = unit_vector(rng);
    w -= n * glm::dot(n, w);
    const float d = glm::dot(w, w);
    if (d > 1e-4f) return w / std::sqrt(d);
  }
}

}  // namespace

GeneratedGeometry generate_sphere_uniform(uint64_t seed, JsonReader& params) {
  const auto count = params.integer("count", 20000, 1, 20'000'000);
  const double radius = params.number("radius", 1.0, 1e-4, 1e4);
  const double size = params.number("triangle_size", 0.05, 1e-6, 1e4);

  SplitMix64 rng(mix_seed(seed, 0x5350484552452d55ull));  // "SPHERE-U"
  const auto r = static_cast<float>(radius);
  // Equilateral triangle of edge `size`: circumradius size / sqrt(3); vertices at 90, 210 and 330
  // degrees in the (t, b) plane.
  const auto c = static_cast<float>(size / std::sqrt(3.0));
  const float h = 0.5f * std::sqrt(3.0f);
  GeneratedGeometry g;
  auto& m = g.mesh;
  m.positions.reserve(3 * count);
  m.triangles.reserve(count);
  double area = 0.0;
  for (int64_t i = 0; i < count; ++i) {
    const glm::vec3 centre = in_unit_ball(rng) * r;
    const glm::vec3 n = unit_vector(rng);
    const glm::vec3 t = perpendicular(rng, n);
    const glm::vec3 b = glm::cross(n, t);
    const glm::vec3 p0 = centre + c * b;
    const glm::vec3 p1 = centre + c * (-h * t - 0.5f * b);
    const glm::vec3 p2 = centre + c * (h * t - 0.5f * b);
    const auto base = static_cast<uint32_t>(m.positions.size());
    m.positions.push_back(p0);
    m.positions.push_back(p1);
    m.positions.push_back(p2);
    m.triangles.emplace_back(base, base + 1, base + 2);
    area += 0.5 * glm::length(glm::dvec3(glm::cross(p1 - p0, p2 - p0)));
  }
  const double volume = 4.0 / 3.0 * kPi * radius * radius * radius;
  g.facts = {{"envelope", {{"center", {0.0, 0.0, 0.0}}, {"radius", radius}}},
             {"leaf_area", area},
             {"leaf_count", count},
             {"triangle_size", size},
             {"leaf_density", static_cast<double>(count) / volume},
             {"leaf_area_density", area / volume}};
  return g;
}

}  // namespace aoeval
