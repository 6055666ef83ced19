// Deterministic primitives: plane, box, disk, geodesic sphere and capped cylinder.
//
// They build the analytic scenes that STYLE.md asks tests to use (an open plane, the inside of a
// closed box, a disk above a plane), the ground under trees and grass (Hegeman et al. 2006, Fig. 9
// tree-ground interaction) and the walls of the interiors. The seed is ignored: the same params
// give the same mesh.
//
// Conventions (CONTRACT §3: right-handed, +Y up). Counter-clockwise triangles are the front. Where
// a shape lies in or on the plane y = 0 it is placed so that it stands on it:
//   plane     the rectangle [-x/2, x/2] x {0} x [-z/2, z/2], facing +Y
//   box       min corner (-x/2, 0, -z/2), max corner (x/2, y, z/2): it stands on y = 0, centred on
//             the Y axis; faces point outward, or toward the box centre with inward = true
//   disk      centred at the origin in y = 0, facing +Y ("up", default) or -Y ("down")
//   sphere    centred at the origin
//   cylinder  axis along +Y from y = 0 to y = height, centred on the Y axis
// Flat shapes carry no vertex normals (geometric normals are exact); the sphere and the cylinder
// carry smooth analytic ones. Trigonometry is evaluated in double and rounded to float, so a
// last-ulp difference between two platforms' libm changes a float only in the rare case where it
// straddles a rounding boundary.

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <unordered_map>

#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Appends an nu x nv grid of quads spanning origin + [0,1] u + [0,1] v, two triangles per quad,
// whose front faces along cross(u, v).
void add_grid(TriangleMesh& m, glm::dvec3 origin, glm::dvec3 u, glm::dvec3 v, int nu, int nv) {
  const auto base = static_cast<uint32_t>(m.positions.size());
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      glm::dvec3 p = origin + u * (static_cast<double>(i) / nu) + v * (static_cast<double>(j) / nv);
      m.positions.emplace_back(p);
    }
  }
  auto idx = [&](int i, int j) { return base + static_cast<uint32_t>(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      m.triangles.emplace_back(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1));
      m.triangles.emplace_back(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1));
    }
  }
}

// Area of a regular n-gon inscribed in a circle of radius r.
double polygon_area(int n, double r) {
  return 0.5 * n * r * r * std::sin(2.0 * kPi / n);
}

nlohmann::json json3(glm::dvec3 v) {
  return {v.x, v.y, v.z};
}

}  // namespace

GeneratedGeometry generate_plane(uint64_t /*seed*/, JsonReader& params) {
  const auto size = params.number_pair("size", {10.0, 10.0}, 1e-6, 1e6);
  const int n = static_cast<int>(params.integer("subdivisions", 1, 1, 2048));
  GeneratedGeometry g;
  // cross(+Z, +X) = +Y: the front faces up.
  add_grid(g.mesh, {-0.5 * size[0], 0.0, -0.5 * size[1]}, {0.0, 0.0, size[1]}, {size[0], 0.0, 0.0},
           n, n);
  g.facts = {{"size", {size[0], size[1]}}, {"area", size[0] * size[1]}};
  return g;
}

GeneratedGeometry generate_box(uint64_t /*seed*/, JsonReader& params) {
  const glm::vec3 size = params.vec3("size", glm::vec3(1.0f));
  for (int i = 0; i < 3; ++i) {
    if (!(size[i] >= 1e-6f && size[i] <= 1e6f))
      params.fail("size", "each value must lie in [1e-06, 1e+06]");
  }
  const bool inward = params.boolean("inward", false);
  const int n = static_cast<int>(params.integer("subdivisions", 1, 1, 1024));
  const std::array<const char*, 6> names = {"+x", "-x", "+y", "-y", "+z", "-z"};
  std::array<bool, 6> open{};
  if (params.has("open")) {
    const auto& j = params.raw("open");
    if (!j.is_array()) params.fail("open", "expected an array of face names (+x -x +y -y +z -z)");
    for (const auto& e : j) {
      bool found = false;
      for (size_t f = 0; f < names.size(); ++f) {
        if (e.is_string() && e.get<std::string>() == names[f]) {
          if (open[f]) params.fail("open", "face " + std::string(names[f]) + " is listed twice");
          open[f] = found = true;
        }
      }
      if (!found) params.fail("open", e.dump() + " is not one of: +x, -x, +y, -y, +z, -z");
    }
    if (j.size() == 6) params.fail("open", "all six faces are open: nothing is left to generate");
  }
  const double x = size.x, y = size.y, z = size.z, hx = 0.5 * x, hz = 0.5 * z;
  struct Face {
    glm::dvec3 origin, u, v;  // outward front along cross(u, v)
  };
  const std::array<Face, 6> faces = {{
      {{hx, 0, -hz}, {0, y, 0}, {0, 0, z}},   // +x: cross(Y, Z) = +X
      {{-hx, 0, -hz}, {0, 0, z}, {0, y, 0}},  // -x
      {{-hx, y, -hz}, {0, 0, z}, {x, 0, 0}},  // +y
      {{-hx, 0, -hz}, {x, 0, 0}, {0, 0, z}},  // -y
      {{-hx, 0, hz}, {x, 0, 0}, {0, y, 0}},   // +z
      {{-hx, 0, -hz}, {0, y, 0}, {x, 0, 0}},  // -z
  }};
  GeneratedGeometry g;
  double area = 0.0;
  nlohmann::json kept = nlohmann::json::array();
  for (size_t f = 0; f < faces.size(); ++f) {
    if (open[f]) continue;
    const Face& fc = faces[f];
    if (inward) {
      add_grid(g.mesh, fc.origin, fc.v, fc.u, n, n);  // swapping u and v flips the front
    } else {
      add_grid(g.mesh, fc.origin, fc.u, fc.v, n, n);
    }
    area += glm::length(glm::cross(fc.u, fc.v));
    kept.push_back(names[f]);
  }
  g.facts = {{"min", json3({-hx, 0.0, -hz})},
             {"max", json3({hx, y, hz})},
             {"inward", inward},
             {"faces", kept},
             {"area", area}};
  return g;
}

GeneratedGeometry generate_disk(uint64_t /*seed*/, JsonReader& params) {
  const double r = params.number("radius", 1.0, 1e-6, 1e6);
  const int n = static_cast<int>(params.integer("segments", 64, 3, 1 << 20));
  const bool up = params.choice("facing", "up", {"up", "down"}) == "up";
  GeneratedGeometry g;
  auto& m = g.mesh;
  m.positions.reserve(n + 1);
  m.positions.emplace_back(0.0f);
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    m.positions.emplace_back(glm::dvec3(r * std::cos(a), 0.0, r * std::sin(a)));
  }
  for (uint32_t k = 0; k < static_cast<uint32_t>(n); ++k) {
    const uint32_t a = 1 + k, b = 1 + (k + 1) % static_cast<uint32_t>(n);
    // Angles run from +X toward +Z, so (centre, a, b) faces -Y.
    if (up) {
      m.triangles.emplace_back(0u, b, a);
    } else {
      m.triangles.emplace_back(0u, a, b);
    }
  }
  g.facts = {{"radius", r}, {"facing", up ? "up" : "down"}, {"area", polygon_area(n, r)}};
  return g;
}

GeneratedGeometry generate_sphere(uint64_t /*seed*/, JsonReader& params) {
  const double r = params.number("radius", 1.0, 1e-6, 1e6);
  const int levels = static_cast<int>(params.integer("subdivisions", 4, 0, 8));
  // The icosahedron, counter-clockwise seen from outside.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                  {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                  {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                  {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::unordered_map<uint64_t, uint32_t> midpoint;  // edge (lo, hi) -> new vertex
    auto mid = [&](uint32_t a, uint32_t b) {
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, inserted] = midpoint.try_emplace(key, static_cast<uint32_t>(v.size()));
      if (inserted) v.push_back(glm::normalize(v[a] + v[b]));
      return it->second;
    };
    std::vector<glm::uvec3> next;
    next.reserve(tris.size() * 4);
    for (const auto& tri : tris) {
      const uint32_t ab = mid(tri.x, tri.y), bc = mid(tri.y, tri.z), ca = mid(tri.z, tri.x);
      next.emplace_back(tri.x, ab, ca);
      next.emplace_back(tri.y, bc, ab);
      next.emplace_back(tri.z, ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    tris = std::move(next);
  }
  GeneratedGeometry g;
  g.mesh.positions.reserve(v.size());
  g.mesh.normals.reserve(v.size());
  for (const auto& p : v) {
    g.mesh.positions.emplace_back(p * r);
    g.mesh.normals.emplace_back(p);  // the exact sphere normal
  }
  g.mesh.triangles = std::move(tris);
  g.facts = {{"center", {0.0, 0.0, 0.0}}, {"radius", r}};
  return g;
}

GeneratedGeometry generate_cylinder(uint64_t /*seed*/, JsonReader& params) {
  const double r = params.number("radius", 0.5, 1e-6, 1e6);
  const double h = params.number("height", 1.0, 1e-6, 1e6);
  const int n = static_cast<int>(params.integer("segments", 32, 3, 1 << 20));
  const bool caps = params.boolean("caps", true);
  GeneratedGeometry g;
  auto& m = g.mesh;
  std::vector<glm::dvec2> ring(n);
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    ring[k] = {std::cos(a), std::sin(a)};
  }
  const auto un = static_cast<uint32_t>(n);
  // Side: vertices k (bottom) and n + k (top), with radial normals.
  for (int level = 0; level < 2; ++level) {
    for (const auto& c : ring) {
      m.positions.emplace_back(glm::dvec3(r * c.x, level * h, r * c.y));
      m.normals.emplace_back(glm::dvec3(c.x, 0.0, c.y));
    }
  }
  for (uint32_t k = 0; k < un; ++k) {
    const uint32_t k1 = (k + 1) % un;
    m.triangles.emplace_back(k, un + k, un + k1);  // outward: angles run from +X toward +Z
    m.triangles.emplace_back(k, un + k1, k1);
  }
  if (caps) {
    for (int top = 0; top < 2; ++top) {
      const auto centre = static_cast<uint32_t>(m.positions.size());
      m.positions.emplace_back(glm::dvec3(0.0, top * h, 0.0));
      for (const auto& c : ring) m.positions.emplace_back(glm::dvec3(r * c.x, top * h, r * c.y));
      for (int k = 0; k <= n; ++k) m.normals.emplace_back(0.0f, top ? 1.0f : -1.0f, 0.0f);
      for (uint32_t k = 0; k < un; ++k) {
        const uint32_t a = centre + 1 + k, b = centre + 1 + (k + 1) % un;
        if (top) {
          m.triangles.emplace_back(centre, b, a);  // faces +Y
        } else {
          m.triangles.emplace_back(centre, a, b);  // faces -Y
        }
      }
    }
  }
  const double side = n * 2.0 * r * std::sin(kPi / n) * h;
  g.facts = {{"radius", r},
             {"height", h},
             {"caps", caps},
             {"area", side + (caps ? 2.0 * polygon_area(n, r) : 0.0)}};
  return g;
}

}  // namespace aoeval
