// tree: a trunk, recursive tapered branches and leaf clusters at the twigs, grown to fill an
// axis-aligned crown ellipsoid. The test objects of Hegeman et al. 2006 ("Approximate Ambient
// Occlusion For Trees"):
//   style "apple"   a round, broad crown (their 550k-triangle apple tree, Fig. 2 bottom row and
//                   Fig. 7) that a single sphere approximates reasonably; about 300k triangles;
//   style "poplar"  a tall columnar crown, about 3:1 height to width (their "ellipsoidal" tree,
//                   Fig. 3 right and Fig. 8), which an ellipsoid fits well and a sphere badly.
// The style only chooses the defaults; every parameter can be overridden.
//
// Growth. The crown is the ellipsoid with radii (crown_radius, crown_height / 2, crown_radius)
// whose top touches y = height, centred on the Y axis. The trunk rises from the origin into the
// crown for a fraction `leader` of its height (apple: a short trunk splitting into scaffold limbs,
// the topmost of which continues upward; poplar: a leader running most of the way up). `branches`
// limbs leave the trunk inside the crown on a golden-angle spiral, spaced by crown volume (fewer
// where the crown is narrow), at an angle to it from `limb_angle_deg` (lowest) to
// `branch_angle_deg` (highest). A limb reaches a random 65-90% of the way to the envelope. Each
// branch carries `sub_branches` children at `branch_angle_deg`, each `length_ratio` times as long
// and shortened (or steered toward the crown centre) to stay inside the crown, for `depth` levels;
// the last level are the twigs, which carry the leaves. `tropism` pulls every branch up (> 0) or
// down (< 0). Radii taper along each branch and shrink by `radius_ratio` per level.
// With the defaults the leaves fill the crown fairly evenly (measured over seeds 1-4): per tenth
// of the crown's height, the leaf count is 0.4-1.9x its share of the crown volume, except the
// poplar's bottom tenth (0.1-0.7x); leaves are somewhat denser in the outer shell than inside.
//
// Geometry. Branches are open tubes of few sides (trunk `sides`, two fewer per level, at least 3).
// Leaves are kites (2 triangles) of length `leaf_size` and width leaf_width * leaf_size, randomly
// oriented (their axis leaning along the twig), scattered along the outer 80% of each twig within
// `leaf_spread` of it. Every leaf lies entirely inside the crown ellipsoid (a leaf that would poke
// out is redrawn closer to its twig; after 8 tries it is dropped, which happens rarely, so
// leaf_count is reported, not assumed). Triangles: first all wood (facts.wood_triangles of them),
// then 2 per leaf. No vertex normals (leaves are flat and surfaces are two-sided).
//
// Determinism: SplitMix64 only; directions are rejection-sampled and the golden-angle rotation is a
// constant, so the only libm calls are cos/sin of the parameter angles and of the tube sides,
// evaluated in double and rounded to float.

// First: no FMA contraction in this file (same bits on every platform).
#include "scenes/generators/fp_contract_off.h"  // IWYU pragma: keep

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <limits>

#include "scenes/generators/generators.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxTriangles = 50'000'000;
const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

struct TreeParams {
  double height, crown_height, crown_radius, leader, trunk_radius;
  int branches, sub_branches, depth, leaves_per_twig, sides;
  double branch_angle_deg, limb_angle_deg, length_ratio, radius_ratio, tropism;
  double leaf_size, leaf_width, leaf_spread;
};

// Every draw is its own statement: the evaluation order of function arguments is unspecified (GCC
// goes right to left, Clang left to right), and the bits must not depend on the compiler.
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

glm::vec3 in_unit_ball(SplitMix64& rng) {
  for (;;) {
    const float x = rng.uniform(-1.0f, 1.0f);
    const float y = rng.uniform(-1.0f, 1.0f);
    const float z = rng.uniform(-1.0f, 1.0f);
    const glm::vec3 p(x, y, z);
    if (glm::dot(p, p) <= 1.0f) return p;
  }
}

glm::vec3 safe_normalize(glm::vec3 v, glm::vec3 fallback) {
  const float d = glm::dot(v, v);
  return d > 1e-12f ? v / std::sqrt(d) : fallback;
}

// Any unit vector perpendicular to the unit vector d.
glm::vec3 any_perpendicular(glm::vec3 d) {
  const glm::vec3 helper = std::fabs(d.y) < 0.9f ? kUp : glm::vec3(1.0f, 0.0f, 0.0f);
  return glm::normalize(glm::cross(d, helper));
}

struct Ellipsoid {
  glm::vec3 center, radii;
  bool contains(glm::vec3 p) const {
    const glm::vec3 q = (p - center) / radii;
    return glm::dot(q, q) <= 1.0f;
  }
  // Distance from p along the unit direction d to the boundary (0 when p is outside).
  float exit_distance(glm::vec3 p, glm::vec3 d) const {
    const glm::vec3 q = (p - center) / radii, e = d / radii;
    const float a = glm::dot(e, e), b = glm::dot(q, e), c = glm::dot(q, q) - 1.0f;
    if (c > 0.0f) return 0.0f;
    return (-b + std::sqrt(std::max(0.0f, b * b - a * c))) / a;
  }
};

class TreeBuilder {
 public:
  TreeBuilder(const TreeParams& p, uint64_t seed, const Ellipsoid& crown)
      : p_(p), rng_(mix_seed(seed, 0x54524545ull)), crown_(crown) {
    cos_angle_ = static_cast<float>(std::cos(p.branch_angle_deg * kPi / 180.0));
    sin_angle_ = static_cast<float>(std::sin(p.branch_angle_deg * kPi / 180.0));
    for (int s = 3; s <= p.sides; ++s) {
      ring_[s].resize(s);
      for (int k = 0; k < s; ++k) {
        const double a = 2.0 * kPi * k / s;
        ring_[s][k] = {static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a))};
      }
    }
  }

  void grow_trunk() {
    const double crown_bottom = p_.height - p_.crown_height;
    const auto top = static_cast<float>(crown_bottom + p_.leader * p_.crown_height);
    const auto first = static_cast<float>(crown_bottom + 0.05 * p_.crown_height);
    grow(glm::vec3(0.0f), kUp, top, static_cast<float>(p_.trunk_radius), 0, first / top);
  }

  TriangleMesh wood, leaves;
  double leaf_area = 0.0;
  int64_t twigs = 0;

 private:
  struct Polyline {
    std::vector<glm::vec3> points;
    float base_radius, tip_radius;
    glm::vec3 at(float t, glm::vec3* dir) const {
      const auto segs = static_cast<int>(points.size()) - 1;
      const float s = t * static_cast<float>(segs);
      const int i = std::min(static_cast<int>(s), segs - 1);
      *dir = safe_normalize(points[i + 1] - points[i], kUp);
      return points[i] + (s - static_cast<float>(i)) * (points[i + 1] - points[i]);
    }
    float radius(float t) const { return base_radius + (tip_radius - base_radius) * t; }
  };

  // Grows one branch of `level` from `start` and, recursively, its children (which start at
  // parameters t >= t_first along it).
  void grow(glm::vec3 start, glm::vec3 dir, float length, float radius, int level, float t_first) {
    Polyline line;
    const int segs = level == 0 ? 4 : (level == 1 ? 2 : 1);
    line.points.push_back(start);
    glm::vec3 d = dir;
    for (int k = 0; k < segs; ++k) {
      if (k > 0) {
        const float wobble = level == 0 ? 0.04f : 0.15f;
        d = glm::normalize(d + wobble * unit_vector(rng_) +
                           (level == 0 ? 0.0f : 0.5f * static_cast<float>(p_.tropism)) * kUp);
        if (level == 0) d = safe_normalize(glm::vec3(d.x, std::max(d.y, 0.95f), d.z), kUp);
      }
      line.points.push_back(line.points.back() + d * (length / static_cast<float>(segs)));
    }
    line.base_radius = radius;
    line.tip_radius = radius * (level == 0 ? static_cast<float>(1.0 - 0.8 * p_.leader) : 0.5f);
    add_tube(line, std::max(3, p_.sides - 2 * level));

    if (level == p_.depth) {
      ++twigs;
      add_leaves(line);
      return;
    }
    const int n = level == 0 ? p_.branches : p_.sub_branches;
    // Golden-angle spiral of azimuths, from a random start.
    glm::vec2 az = random_direction_2d();
    const glm::vec2 golden(-0.73736887807831974f, 0.67549029426152364f);  // cos, sin 137.5 deg
    for (int i = 0; i < n; ++i) {
      const float u = rng_.uniform_float();
      const float q = (static_cast<float>(i) + 0.1f + 0.8f * u) / static_cast<float>(n);
      float t = t_first + (1.0f - t_first) * q;
      if (level == 0) {
        // Limbs are spaced by crown volume, not by height: fewer where the crown is narrow.
        const double top = line.points.back().y;
        t = static_cast<float>(volume_quantile(t_first * top, top, q) / top);
      }
      glm::vec3 pdir;
      const glm::vec3 p = line.at(t, &pdir);
      const glm::vec3 a = any_perpendicular(pdir), b = glm::cross(pdir, a);
      az = glm::vec2(az.x * golden.x - az.y * golden.y, az.x * golden.y + az.y * golden.x);
      // The trunk's topmost child continues it upward (the apex); the others fan out.
      const bool apex = level == 0 && i == n - 1 && n > 1 && p_.leader < 0.5;
      float ca = cos_angle_, sa = sin_angle_;
      if (level == 0) {
        // Limbs: from limb_angle_deg at the lowest to branch_angle_deg at the top of the trunk.
        const double f = n > 1 ? static_cast<double>(i) / (n - 1) : 1.0;
        const double deg = p_.limb_angle_deg + (p_.branch_angle_deg - p_.limb_angle_deg) * f;
        ca = static_cast<float>(std::cos(deg * kPi / 180.0));
        sa = static_cast<float>(std::sin(deg * kPi / 180.0));
      }
      glm::vec3 cd = apex ? pdir : pdir * ca + (a * az.x + b * az.y) * sa;
      cd = glm::normalize(cd + 0.15f * unit_vector(rng_));
      cd = safe_normalize(cd + static_cast<float>(p_.tropism) * kUp, cd);
      float avail = crown_.exit_distance(p, cd);
      float nominal = length * static_cast<float>(p_.length_ratio) * rng_.uniform(0.8f, 1.2f);
      if (level == 0) {
        // A limb reaches 65-90% of the way to the envelope, measured sideways (the crown's local
        // radius at its height) so that steep limbs low in a columnar crown stay short.
        const float y = (p.y - crown_.center.y) / crown_.radii.y;
        const float local = crown_.radii.x * std::sqrt(std::max(0.0f, 1.0f - y * y));
        const float side = std::sqrt(cd.x * cd.x + cd.z * cd.z);
        const float reach = apex ? avail : std::min(avail, local / std::max(side, 0.25f));
        nominal = reach * rng_.uniform(0.65f, 0.9f);
      }
      if (level > 0 && avail < 0.5f * nominal) {  // steer toward the crown centre
        const glm::vec3 in = safe_normalize(crown_.center - p, -cd);
        for (int k = 1; k <= 3 && avail < 0.5f * nominal; ++k) {
          const glm::vec3 d2 = glm::normalize(cd + (0.5f * static_cast<float>(k)) * in);
          const float a2 = crown_.exit_distance(p, d2);
          if (a2 > avail) {
            cd = d2;
            avail = a2;
          }
        }
      }
      if (level == 0 && nominal < 1e-3f * static_cast<float>(p_.crown_radius)) {
        nominal = 0.3f * static_cast<float>(p_.crown_radius);  // start on the crown's boundary
      }
      const float len = std::max(std::min(nominal, 0.92f * avail), 0.3f * nominal);
      const float r = std::max(line.radius(t) * static_cast<float>(p_.radius_ratio), 1e-4f);
      grow(p, cd, len, r, level + 1, 0.3f);
    }
  }

  // The height y in [y0, y1] below which a fraction q of the crown's volume between y0 and y1
  // lies (bisection on the slab volume, whose cross-section is proportional to 1 - y_n^2).
  double volume_quantile(double y0, double y1, double q) const {
    const double c = crown_.center.y, r = crown_.radii.y;
    auto volume = [&](double y) {
      const double yn = std::clamp((y - c) / r, -1.0, 1.0);
      return yn - yn * yn * yn / 3.0;
    };
    const double v0 = volume(y0), target = v0 + q * (volume(y1) - v0);
    double lo = y0, hi = y1;
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (volume(mid) < target ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }

  glm::vec2 random_direction_2d() {
    for (;;) {
      const float x = rng_.uniform(-1.0f, 1.0f);
      const float y = rng_.uniform(-1.0f, 1.0f);
      const glm::vec2 q(x, y);
      const float d = glm::dot(q, q);
      if (d <= 1.0f && d > 1e-4f) return q / std::sqrt(d);
    }
  }

  // An open tube along the polyline: one ring of `sides` vertices per point.
  void add_tube(const Polyline& line, int sides) {
    const auto& ring = ring_[sides];
    const auto base = static_cast<uint32_t>(wood.positions.size());
    const auto n = static_cast<uint32_t>(sides);
    glm::vec3 a = any_perpendicular(safe_normalize(line.points[1] - line.points[0], kUp));
    const size_t count = line.points.size();
    for (size_t k = 0; k < count; ++k) {
      const glm::vec3 d = safe_normalize(
          line.points[std::min(k + 1, count - 1)] - line.points[k == 0 ? 0 : k - 1], kUp);
      a = safe_normalize(a - d * glm::dot(a, d), any_perpendicular(d));  // parallel transport
      const glm::vec3 b = glm::cross(d, a);
      const float r = line.radius(static_cast<float>(k) / static_cast<float>(count - 1));
      for (const auto& c : ring) wood.positions.push_back(line.points[k] + r * (c.x * a + c.y * b));
    }
    for (uint32_t k = 0; k + 1 < count; ++k) {
      for (uint32_t j = 0; j < n; ++j) {
        const uint32_t j1 = (j + 1) % n;
        const uint32_t p00 = base + k * n + j, p01 = base + k * n + j1;
        const uint32_t p10 = p00 + n, p11 = p01 + n;
        wood.triangles.emplace_back(p00, p01, p11);  // outward: angles run from a toward b = d x a
        wood.triangles.emplace_back(p00, p11, p10);
      }
    }
  }

  void add_leaves(const Polyline& twig) {
    const auto len = static_cast<float>(p_.leaf_size);
    const auto half_width = static_cast<float>(0.5 * p_.leaf_width * p_.leaf_size);
    const auto spread = static_cast<float>(p_.leaf_spread);
    for (int i = 0; i < p_.leaves_per_twig; ++i) {
      float reach = 1.0f;
      for (int attempt = 0; attempt < 8; ++attempt, reach *= 0.5f) {
        glm::vec3 d;
        const glm::vec3 attach = twig.at(rng_.uniform(0.2f, 1.0f), &d);
        const glm::vec3 base = attach + (spread * reach) * in_unit_ball(rng_);
        const glm::vec3 axis = safe_normalize(unit_vector(rng_) + 0.7f * d, d);
        const glm::vec3 w =
            safe_normalize(glm::cross(axis, unit_vector(rng_)), any_perpendicular(axis));
        const glm::vec3 mid = base + 0.5f * len * axis;
        const glm::vec3 v[4] = {base, mid + half_width * w, base + len * axis,
                                mid - half_width * w};
        if (!(crown_.contains(v[0]) && crown_.contains(v[1]) && crown_.contains(v[2]) &&
              crown_.contains(v[3]))) {
          continue;
        }
        const auto k = static_cast<uint32_t>(leaves.positions.size());
        leaves.positions.insert(leaves.positions.end(), v, v + 4);
        leaves.triangles.emplace_back(k, k + 1, k + 2);
        leaves.triangles.emplace_back(k, k + 2, k + 3);
        leaf_area += 0.5 * glm::length(glm::dvec3(glm::cross(v[2] - v[0], v[1] - v[3])));
        break;
      }
    }
  }

  const TreeParams& p_;
  SplitMix64 rng_;
  Ellipsoid crown_;
  float cos_angle_ = 0.0f, sin_angle_ = 0.0f;
  std::vector<glm::vec2> ring_[65];
};

nlohmann::json json3(glm::vec3 v) {
  return {v.x, v.y, v.z};
}

}  // namespace

GeneratedGeometry generate_tree(uint64_t seed, JsonReader& params) {
  const bool apple = params.choice("style", "apple", {"apple", "poplar"}) == "apple";
  TreeParams p;
  p.height = params.number("height", apple ? 4.5 : 12.0, 0.01, 1e4);
  p.crown_height = params.number("crown_height", apple ? 3.2 : 10.0, 0.005, 1e4);
  p.crown_radius = params.number("crown_radius", apple ? 2.0 : 1.6, 0.0025, 1e4);
  p.leader = params.number("leader", apple ? 0.3 : 0.85, 0.05, 0.98);
  p.trunk_radius = params.number("trunk_radius", apple ? 0.12 : 0.15, 1e-5, 1e3);
  p.branches = static_cast<int>(params.integer("branches", apple ? 7 : 36, 1, 1000));
  p.sub_branches = static_cast<int>(params.integer("sub_branches", apple ? 5 : 4, 1, 100));
  p.depth = static_cast<int>(params.integer("depth", apple ? 5 : 4, 1, 8));
  p.branch_angle_deg = params.number("branch_angle_deg", apple ? 50.0 : 45.0, 0.0, 120.0);
  p.limb_angle_deg = params.number("limb_angle_deg", apple ? 50.0 : 80.0, 0.0, 120.0);
  p.length_ratio = params.number("length_ratio", apple ? 0.6 : 0.55, 0.05, 1.5);
  p.radius_ratio = params.number("radius_ratio", 0.55, 0.05, 1.0);
  p.tropism = params.number("tropism", apple ? -0.05 : 0.15, -1.0, 1.0);
  p.leaves_per_twig =
      static_cast<int>(params.integer("leaves_per_twig", apple ? 31 : 50, 1, 10000));
  p.leaf_size = params.number("leaf_size", apple ? 0.04 : 0.05, 1e-5, 1e3);
  p.leaf_width = params.number("leaf_width", 0.6, 0.05, 2.0);
  p.leaf_spread = params.number("leaf_spread", 2.0 * p.leaf_size, 0.0, 1e3);
  p.sides = static_cast<int>(params.integer("sides", 8, 3, 64));

  if (p.crown_height > p.height) params.fail("crown_height", "must not exceed height");
  if (p.leaf_size > 0.25 * std::min(p.crown_radius, 0.5 * p.crown_height)) {
    params.fail("leaf_size", "must be at most a quarter of the crown's smallest radius");
  }
  // Leaves dominate: about 2 triangles per leaf and at most 2 * sides * 4 per branch.
  double twigs = p.branches, all_branches = 1.0 + p.branches;
  for (int level = 2; level <= p.depth; ++level) {
    twigs *= p.sub_branches;
    all_branches += twigs;
  }
  const double estimate = twigs * p.leaves_per_twig * 2.0 + all_branches * 8.0 * p.sides;
  if (estimate > kMaxTriangles) {
    params.fail("depth", "the tree would have about " + std::to_string(estimate) +
                             " triangles (at most " + std::to_string(kMaxTriangles) +
                             "); lower depth, branches, sub_branches or leaves_per_twig");
  }

  const Ellipsoid crown{
      glm::vec3(0.0f, static_cast<float>(p.height - 0.5 * p.crown_height), 0.0f),
      glm::vec3(glm::dvec3(p.crown_radius, 0.5 * p.crown_height, p.crown_radius))};
  TreeBuilder builder(p, seed, crown);
  builder.wood.positions.reserve(static_cast<size_t>(all_branches * 3.0 * p.sides));
  builder.wood.triangles.reserve(static_cast<size_t>(all_branches * 2.0 * p.sides));
  builder.leaves.positions.reserve(static_cast<size_t>(twigs * p.leaves_per_twig * 4.0));
  builder.leaves.triangles.reserve(static_cast<size_t>(twigs * p.leaves_per_twig * 2.0));
  builder.grow_trunk();
  if (builder.leaves.triangles.empty()) {
    params.fail("leaf_size", "no leaf fits inside the crown; make the leaves smaller");
  }

  // The leaves' bounding box and a bounding sphere centred on it (Hegeman et al. §3: "a simple
  // spherical bounding box computation"; it encloses every leaf but is not the minimal sphere).
  const Bounds leaf_bounds = builder.leaves.bounds();
  const glm::vec3 centre = leaf_bounds.center();
  float r2 = 0.0f;
  for (const auto& v : builder.leaves.positions)
    r2 = std::max(r2, glm::dot(v - centre, v - centre));
  const double sphere_radius = std::nextafter(std::sqrt(r2), std::numeric_limits<float>::max());

  GeneratedGeometry g;
  const auto wood_triangles = static_cast<int64_t>(builder.wood.triangle_count());
  const auto leaf_count = static_cast<int64_t>(builder.leaves.triangle_count() / 2);
  g.mesh = std::move(builder.wood);
  g.mesh.append(builder.leaves);
  const double volume = 4.0 / 3.0 * kPi * p.crown_radius * p.crown_radius * 0.5 * p.crown_height;
  g.facts = {
      {"style", apple ? "apple" : "poplar"},
      {"height", p.height},
      {"leaf_area", builder.leaf_area},
      {"leaf_count", leaf_count},
      {"twig_count", builder.twigs},
      {"wood_triangles", wood_triangles},
      {"crown",
       {{"center", {0.0, p.height - 0.5 * p.crown_height, 0.0}},
        {"radii", {p.crown_radius, 0.5 * p.crown_height, p.crown_radius}}}},
      {"crown_volume", volume},
      {"leaf_area_density", builder.leaf_area / volume},
      {"leaf_bounds", {{"min", json3(leaf_bounds.lower)}, {"max", json3(leaf_bounds.upper)}}},
      {"bounding_sphere", {{"center", json3(centre)}, {"radius", sphere_radius}}}};
  return g;
}

}  // namespace aoeval
