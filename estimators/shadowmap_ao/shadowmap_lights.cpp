// The light directions of shadowmap-ao (GPU Gems ch. 17 §17.3: "you should use a uniform
// distribution on the sphere", not "evenly spaced longitudes and latitudes").
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <numbers>

#include "base/errors.h"
#include "estimators/shadowmap_ao/shadowmap_ao.h"
#include "scenes/random.h"

namespace aoeval {

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 spherical(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), cos_theta, s * std::sin(phi)};  // polar axis +Y
}

// A uniformly random rotation (Shoemake 1992, "Uniform random rotations", from three uniforms).
glm::dquat random_rotation(SplitMix64& g) {
  const double u1 = g.uniform_double(), u2 = g.uniform_double(), u3 = g.uniform_double();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return glm::dquat(a * std::sin(2 * kPi * u2), a * std::cos(2 * kPi * u2),
                    b * std::sin(2 * kPi * u3), b * std::cos(2 * kPi * u3));
}

}  // namespace

std::vector<glm::vec3> light_directions(int count, LightDistribution distribution, bool dome,
                                        uint64_t seed) {
  if (count < 1) throw InputError("lights: must be at least 1");
  SplitMix64 g(mix_seed(seed, 0x5AD0));
  std::vector<glm::dvec3> d;
  d.reserve(count);
  const auto n = static_cast<double>(count);
  if (distribution == LightDistribution::uniform) {
    // Spherical Fibonacci lattice: cos θ uniform in equal steps (equal-area bands, Archimedes) and
    // longitude advanced by the golden angle, so every light stands for the same solid angle,
    // 4π/n (sphere) or 2π/n (dome), and the points are spread without clumps or poles.
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
      const double c = dome ? (i + 0.5) / n : 1.0 - (2.0 * i + 1.0) / n;
      d.push_back(spherical(c, golden * i));
    }
    // A seeded random rotation keeps the set uniform in distribution; the dome may only turn about
    // +Y, so it stays above the ground plane.
    if (dome) {
      const double a = 2 * kPi * g.uniform_double();
      for (auto& v : d)
        v = {std::cos(a) * v.x - std::sin(a) * v.z, v.y, std::sin(a) * v.x + std::cos(a) * v.z};
    } else {
      const glm::dquat q = random_rotation(g);
      for (auto& v : d) v = q * v;
    }
  } else {
    // Evenly spaced latitudes θ_j and longitudes: rows at θ = (j + 1/2) Δθ, Δθ = π / rows (sphere)
    // or (π/2) / rows (dome), and about as many longitudes as make Δφ = Δθ (2 rows per longitude
    // ring on the sphere, 4 on the dome), the n lights shared out as evenly as the rows allow.
    // Each ring holds the same count whatever its circumference: the poles get the same number of
    // lights as the equator, the concentration the chapter warns of.
    const int rows = std::max(1, static_cast<int>(std::lround(std::sqrt(n / (dome ? 4.0 : 2.0)))));
    const double span = dome ? kPi / 2 : kPi;
    const double offset = g.uniform_double();  // the longitudes' seeded phase
    for (int j = 0; j < rows; ++j) {
      const int in_row = count / rows + (j < count % rows ? 1 : 0);
      const double theta = span * (j + 0.5) / rows;
      for (int k = 0; k < in_row; ++k)
        d.push_back(spherical(std::cos(theta), 2 * kPi * (k + offset) / in_row));
    }
  }
  std::vector<glm::vec3> out(d.size());
  for (size_t i = 0; i < d.size(); ++i) out[i] = glm::vec3(glm::normalize(d[i]));
  return out;
}

}  // namespace aoeval
