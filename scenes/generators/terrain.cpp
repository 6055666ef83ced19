// terrain: a height field over the rectangle [-x/2, x/2] x [-z/2, z/2] (issue 45, the ground the
// forests stand on), y = amplitude * noise(x, z) + slope.x * x + slope.z * z.
//
// noise is `octaves` octaves of value noise: octave o has lattice spacing feature_length / 2^o and
// weight 2^-o; a lattice node's value is uniform in [-1, 1] from SplitMix64(seed, o, node), and
// between nodes it is interpolated with the quintic smoothstep 6t^5 - 15t^4 + 10t^3 (C2, so the
// slopes change smoothly). The sum is divided by the sum of the weights, so |noise| <= 1 and every
// height lies within amplitude of the tilted plane. Only + and * in double touch a random number:
// the same params give the same bits on every platform.
//
// The mesh is a resolution x resolution grid of cells, two triangles each, facing +Y, without
// vertex normals (the geometric normals are the surface's). Between the vertices the surface is
// the triangles: things placed "on" it (scene.cpp, README "Instanced objects") stand at the
// triangle's interpolated height, not at the noise's. The finest octave must span at least two
// cells, or the grid would alias it.

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include <algorithm>
#include <cmath>

#include "scenes/generators/generators.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

double smooth(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// A lattice node's value in [-1, 1].
double node_value(uint64_t seed, int octave, int64_t i, int64_t j) {
  SplitMix64 g(mix_seed(seed, static_cast<uint64_t>(octave),
                        (static_cast<uint64_t>(i) << 32) ^ static_cast<uint64_t>(j)));
  return 2.0 * g.uniform_double() - 1.0;
}

double value_noise(uint64_t seed, int octave, double x, double z) {
  const double fi = std::floor(x), fj = std::floor(z);
  const auto i = static_cast<int64_t>(fi), j = static_cast<int64_t>(fj);
  const double u = smooth(x - fi), v = smooth(z - fj);
  const double a = node_value(seed, octave, i, j), b = node_value(seed, octave, i + 1, j);
  const double c = node_value(seed, octave, i, j + 1), d = node_value(seed, octave, i + 1, j + 1);
  const double bottom = a + (b - a) * u, top = c + (d - c) * u;
  return bottom + (top - bottom) * v;
}

}  // namespace

GeneratedGeometry generate_terrain(uint64_t seed, JsonReader& params) {
  const auto size = params.number_pair("size", {100.0, 100.0}, 1e-3, 1e6);
  const int n = static_cast<int>(params.integer("resolution", 128, 1, 2048));
  const double amplitude = params.number("amplitude", 2.0, 0.0, 1e5);
  const double feature = params.number("feature_length", 40.0, 1e-3, 1e7);
  const int octaves = static_cast<int>(params.integer("octaves", 3, 1, 12));
  const auto slope = params.number_pair("slope", {0.0, 0.0}, -10.0, 10.0);
  const double cell = std::max(size[0], size[1]) / n;
  const double finest = feature / std::ldexp(1.0, octaves - 1);
  if (amplitude > 0.0 && finest < 2.0 * cell)
    params.fail("feature_length",
                "the finest octave (feature_length / 2^(octaves - 1) = " + std::to_string(finest) +
                    ") is shorter than two cells (" + std::to_string(2.0 * cell) +
                    "); raise resolution or feature_length, or lower octaves");

  double weights = 0.0;
  for (int o = 0; o < octaves; ++o) weights += std::ldexp(1.0, -o);
  GeneratedGeometry g;
  auto& m = g.mesh;
  m.positions.reserve(static_cast<size_t>(n + 1) * static_cast<size_t>(n + 1));
  double lo = INFINITY, hi = -INFINITY;
  for (int b = 0; b <= n; ++b) {
    for (int a = 0; a <= n; ++a) {
      const double x = size[0] * (static_cast<double>(a) / n - 0.5);
      const double z = size[1] * (static_cast<double>(b) / n - 0.5);
      double noise = 0.0;
      if (amplitude > 0.0)
        for (int o = 0; o < octaves; ++o) {
          const double spacing = feature / std::ldexp(1.0, o);
          noise += std::ldexp(1.0, -o) * value_noise(seed, o, x / spacing, z / spacing);
        }
      const double y = amplitude * noise / weights + slope[0] * x + slope[1] * z;
      lo = std::min(lo, y);
      hi = std::max(hi, y);
      m.positions.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    }
  }
  auto idx = [&](int a, int b) { return static_cast<uint32_t>(b * (n + 1) + a); };
  m.triangles.reserve(2 * static_cast<size_t>(n) * static_cast<size_t>(n));
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      // cross(+Z, +X + Z) = +Y and cross(+X + Z, +X) = +Y: both face up.
      m.triangles.emplace_back(idx(a, b), idx(a, b + 1), idx(a + 1, b + 1));
      m.triangles.emplace_back(idx(a, b), idx(a + 1, b + 1), idx(a + 1, b));
    }
  g.facts = {{"size", {size[0], size[1]}},
             {"resolution", n},
             {"amplitude", amplitude},
             {"feature_length", feature},
             {"octaves", octaves},
             {"slope", {slope[0], slope[1]}},
             {"height_range", {lo, hi}},
             {"height_rule",
              "piecewise linear on the cells' triangles; objects placed \"on\" it stand at the "
              "triangle's height"}};
  return g;
}

}  // namespace aoeval
