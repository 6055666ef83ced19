// Thin occluders: a picket fence and a chair with thin legs, the geometry engine teams ask
// screen-space AO about (a depth buffer sees only the front face of a picket or a leg, so a
// heightfield horizon treats it as infinitely thick behind: the thin-occluder problem that GTAO's
// thickness heuristic, Jimenez et al. 2016 §4, and Filament's visibility-bitmask GTAO address).
//
// Both are unions of axis-aligned boxes standing on y = 0, every box closed (12 triangles on its 8
// corners, counter-clockwise outward, no vertex normals: flat faces), so the reference sees true
// thin solids. The seed is ignored: the same params give the same mesh.
//   fence  `pickets` pickets of width x depth x height along X, centred on the origin, `gap` apart,
//          nailed to two rails behind them (z < 0) at 1/4 and 3/4 of the height
//   chair  a seat of side `seat` at `seat_height`, four square legs of side `leg`, a back of two
//          posts and `slats` horizontal slats on the -Z side, up to `back_height` above the seat

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

// Appends the closed box [lo, hi] (12 triangles, fronts outward); returns its surface area.
double add_box(TriangleMesh& m, glm::dvec3 lo, glm::dvec3 hi) {
  const auto base = static_cast<uint32_t>(m.positions.size());
  for (int k = 0; k < 8; ++k)  // corner k: bit 0 -> x, bit 1 -> y, bit 2 -> z at hi
    m.positions.emplace_back(
        glm::dvec3((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z));
  // Each face's corners counter-clockwise seen from outside.
  static const uint32_t kFaces[6][4] = {
      {1, 3, 7, 5},  // +x
      {0, 4, 6, 2},  // -x
      {2, 6, 7, 3},  // +y
      {0, 1, 5, 4},  // -y
      {4, 5, 7, 6},  // +z
      {0, 2, 3, 1},  // -z
  };
  for (const auto& f : kFaces) {
    m.triangles.emplace_back(base + f[0], base + f[1], base + f[2]);
    m.triangles.emplace_back(base + f[0], base + f[2], base + f[3]);
  }
  const glm::dvec3 s = hi - lo;
  return 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
}

}  // namespace

GeneratedGeometry generate_fence(uint64_t /*seed*/, JsonReader& params) {
  const int n = static_cast<int>(params.integer("pickets", 12, 1, 10000));
  const double w = params.number("picket_width", 0.04, 1e-5, 1e3);
  const double d = params.number("picket_depth", 0.02, 1e-5, 1e3);
  const double h = params.number("height", 0.8, 1e-5, 1e3);
  const double gap = params.number("gap", 0.05, 0.0, 1e3);
  const double rail = params.number("rail", 0.03, 1e-5, 1e3);  // side of a rail's square section
  if (rail * 2.0 > h) params.fail("rail", "two rails must fit in the height");
  GeneratedGeometry g;
  const double span = n * w + (n - 1) * gap;
  double area = 0.0;
  for (int k = 0; k < n; ++k) {
    const double x0 = -0.5 * span + k * (w + gap);
    area += add_box(g.mesh, {x0, 0.0, 0.0}, {x0 + w, h, d});
  }
  for (double y : {0.25 * h, 0.75 * h})
    area +=
        add_box(g.mesh, {-0.5 * span, y - 0.5 * rail, -rail}, {0.5 * span, y + 0.5 * rail, 0.0});
  g.facts = {{"span", span}, {"height", h}, {"pickets", n}, {"picket_width", w}, {"area", area}};
  return g;
}

GeneratedGeometry generate_chair(uint64_t /*seed*/, JsonReader& params) {
  const double seat = params.number("seat", 0.45, 1e-3, 1e3);
  const double seat_height = params.number("seat_height", 0.45, 1e-3, 1e3);
  const double leg = params.number("leg", 0.025, 1e-5, 1e3);
  const double board = params.number("board", 0.03, 1e-5, 1e3);  // seat and slat thickness
  const double back = params.number("back_height", 0.45, 1e-3, 1e3);
  const int slats = static_cast<int>(params.integer("slats", 3, 0, 100));
  if (2.0 * leg >= seat) params.fail("leg", "two legs must fit under the seat");
  if (board >= seat_height) params.fail("board", "the seat board must be thinner than its height");
  GeneratedGeometry g;
  const double s = 0.5 * seat, top = seat_height - board;
  double area = add_box(g.mesh, {-s, top, -s}, {s, seat_height, s});
  for (int k = 0; k < 4; ++k) {
    const double x = (k & 1) ? s - leg : -s, z = (k & 2) ? s - leg : -s;
    area += add_box(g.mesh, {x, 0.0, z}, {x + leg, top, z + leg});
  }
  for (double x : {-s, s - leg})  // back posts on the -Z side, above the seat
    area += add_box(g.mesh, {x, seat_height, -s}, {x + leg, seat_height + back, -s + leg});
  for (int k = 0; k < slats; ++k) {
    const double y = seat_height + back * (k + 1) / (slats + 1);
    area += add_box(g.mesh, {-s + leg, y - 0.5 * board, -s}, {s - leg, y + 0.5 * board, -s + leg});
  }
  g.facts = {{"seat_height", seat_height}, {"leg", leg}, {"area", area}};
  return g;
}

}  // namespace aoeval
