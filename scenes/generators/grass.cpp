// grass: a field of thin tapered blades standing on y = 0, for the grass visibility model of
// Hegeman et al. 2006 (§3, Fig. 6 and 10, eq. 9: V = P_z / (2h) (1 + cos theta), where P_z is the
// height of the shaded point on the blade and h the blade's total height).
//
// Because eq. 9 needs h exactly, every blade has the same height and the guarantee is exact, not
// approximate: the blade is built level by level at y = blade_height * k / segments, so
//   - the root vertices of every blade have y == 0 exactly,
//   - the tip vertex of every blade has y == float(blade_height) exactly,
//   - every vertex has 0 <= y <= float(blade_height).
// Lean and bend are purely horizontal: a blade's centre line is root + d * lean_i * h * t^2 at
// height h * t (t in [0, 1]), a parabola that is vertical at the root and leans by at most
// lean * blade_height at the tip, toward a random direction d, with lean_i uniform in [0, lean].
// The blade's width axis is perpendicular to d (it bends toward its face, as real blades do), and
// its width tapers linearly from blade_width at the root to a point at the tip.
//
// Layout: `size` [x, z] rectangle centred at the origin; blade_count = round(density * x * z) roots
// uniform in it (tips may lean up to lean * blade_height beyond its edges). A blade with S segments
// has 2 S + 1 vertices (pairs from root up, then the tip) and 2 S - 1 triangles, stored blade after
// blade. No vertex normals (surfaces are two-sided). Randomness: SplitMix64 only; directions are
// rejection-sampled, so no transcendental function touches a random number.

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "scenes/generators/generators.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

constexpr int64_t kMaxTriangles = 50'000'000;

// Every draw is its own statement: the evaluation order of function arguments is unspecified (GCC
// goes right to left, Clang left to right), and the bits must not depend on the compiler.
// A uniform direction in the XZ plane (rejection in the unit square).
glm::vec2 unit_vector_2d(SplitMix64& rng) {
  for (;;) {
    const float x = rng.uniform(-1.0f, 1.0f);
    const float y = rng.uniform(-1.0f, 1.0f);
    const glm::vec2 p(x, y);
    const float d = glm::dot(p, p);
    if (d <= 1.0f && d > 1e-4f) return p / std::sqrt(d);
  }
}

}  // namespace

GeneratedGeometry generate_grass(uint64_t seed, JsonReader& params) {
  const auto size = params.number_pair("size", {4.0, 4.0}, 1e-3, 1e4);
  const double density = params.number("density", 1000.0, 1e-3, 1e6);
  const double height = params.number("blade_height", 0.3, 1e-4, 1e3);
  const double width = params.number("blade_width", 0.01, 1e-6, 1e2);
  const double lean = params.number("lean", 0.2, 0.0, 1.0);
  const int segments = static_cast<int>(params.integer("segments", 3, 1, 32));

  const double wanted = std::round(density * size[0] * size[1]);
  const int64_t tris_per_blade = 2 * segments - 1;
  if (wanted < 1.0) params.fail("density", "density * area gives no blade at all");
  if (wanted * static_cast<double>(tris_per_blade) > static_cast<double>(kMaxTriangles)) {
    params.fail("density", "the field would have " + std::to_string(wanted * tris_per_blade) +
                               " triangles; at most " + std::to_string(kMaxTriangles));
  }
  const auto blades = static_cast<int64_t>(wanted);

  SplitMix64 rng(mix_seed(seed, 0x4752415353ull));  // "GRASS"
  const auto sx = static_cast<float>(size[0]), sz = static_cast<float>(size[1]);
  const auto h = static_cast<float>(height), w = static_cast<float>(width);
  GeneratedGeometry g;
  auto& m = g.mesh;
  m.positions.reserve(blades * (2 * segments + 1));
  m.triangles.reserve(blades * tris_per_blade);
  double area = 0.0;
  for (int64_t i = 0; i < blades; ++i) {
    const float rx = sx * (rng.uniform_float() - 0.5f);
    const float rz = sz * (rng.uniform_float() - 0.5f);
    const glm::vec3 root(rx, 0.0f, rz);
    const glm::vec2 d = unit_vector_2d(rng);
    const float tip_offset = static_cast<float>(lean) * rng.uniform_float() * h;
    const glm::vec3 dir(d.x, 0.0f, d.y), side(-d.y, 0.0f, d.x);
    const auto base = static_cast<uint32_t>(m.positions.size());
    for (int k = 0; k <= segments; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(segments);  // k == S: exactly 1
      glm::vec3 c = root + dir * (tip_offset * t * t);
      c.y = h * t;  // exact: 0 at the root, h at the tip
      if (k == segments) {
        m.positions.push_back(c);
      } else {
        const float half = 0.5f * w * (1.0f - t);
        m.positions.push_back(c - side * half);
        m.positions.push_back(c + side * half);
      }
    }
    for (uint32_t k = 0; k < static_cast<uint32_t>(segments); ++k) {
      const uint32_t l = base + 2 * k, r = l + 1;
      if (k + 1 == static_cast<uint32_t>(segments)) {
        m.triangles.emplace_back(l, r, r + 1);  // r + 1 is the tip
      } else {
        m.triangles.emplace_back(l, r, r + 2);
        m.triangles.emplace_back(l, r + 2, r + 1);
      }
    }
    for (size_t t = m.triangles.size() - tris_per_blade; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      const glm::dvec3 a(m.positions[tri.x]), b(m.positions[tri.y]), c(m.positions[tri.z]);
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
  }
  g.facts = {{"blade_height", height},
             {"blade_count", blades},
             {"blade_area", area},
             {"size", {size[0], size[1]}},
             {"segments", segments},
             {"height_guarantee",
              "every blade's root vertices have y = 0 and its tip vertex y = blade_height exactly "
              "(as float); lean only moves vertices horizontally"}};
  return g;
}

}  // namespace aoeval
