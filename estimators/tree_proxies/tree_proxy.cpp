#include "estimators/tree_proxies/tree_proxy.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>

#include "base/errors.h"
#include "scenes/instances.h"
#include "scenes/random.h"

namespace aoeval {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string object_where(const SceneObject& o) {
  return "object \"" + o.name + "\" (role tree)";
}

// The smallest float >= x: a radius computed in double and stored as float must still enclose.
float round_up(double x) {
  auto f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::max());
  return f;
}

glm::dvec3 vertex(const SceneObject& o, size_t triangle, int corner) {
  return glm::dvec3(o.mesh.positions[o.mesh.triangles[triangle][corner]]);
}

glm::dvec3 centroid(const SceneObject& o, size_t t) {
  return (vertex(o, t, 0) + vertex(o, t, 1) + vertex(o, t, 2)) / 3.0;
}

double triangle_area(const SceneObject& o, size_t t) {
  return 0.5 * glm::length(glm::cross(vertex(o, t, 1) - vertex(o, t, 0),
                                      vertex(o, t, 2) - vertex(o, t, 0)));
}

Ellipsoid sphere_shape(const glm::dvec3& center, double radius) {
  Ellipsoid e;
  e.center = glm::vec3(center);
  e.radii = glm::vec3(round_up(radius));
  return e;
}

// Bounding-box centre of the leaf vertices.
glm::dvec3 leaf_box_center(const SceneObject& o, const LeafSet& leaves) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (size_t t = leaves.first_triangle; t < o.mesh.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) {
      lo = glm::min(lo, vertex(o, t, c));
      hi = glm::max(hi, vertex(o, t, c));
    }
  return 0.5 * (lo + hi);
}

Ellipsoid derive_ellipsoid(const SceneObject& o, const LeafSet& leaves, double coverage) {
  const glm::dvec3 center = leaf_box_center(o, leaves);
  glm::dvec3 moment(0.0);
  double total = 0.0;
  for (size_t t = leaves.first_triangle; t < o.mesh.triangle_count(); ++t) {
    const double a = triangle_area(o, t);
    const glm::dvec3 q = centroid(o, t) - center;
    moment += a * q * q;
    total += a;
  }
  glm::dvec3 sigma = glm::sqrt(moment / std::max(total, 1e-300));
  // A flat (planar) leaf cloud has no spread along one axis: give it a sliver of the largest.
  const double largest = std::max({sigma.x, sigma.y, sigma.z, 1e-30});
  sigma = glm::max(sigma, glm::dvec3(1e-3 * largest));
  std::vector<double> scale;
  scale.reserve(3 * leaves.triangles);
  for (size_t t = leaves.first_triangle; t < o.mesh.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) scale.push_back(glm::length((vertex(o, t, c) - center) / sigma));
  const auto k = static_cast<size_t>(std::ceil(coverage * static_cast<double>(scale.size()))) - 1;
  std::nth_element(scale.begin(), scale.begin() + static_cast<std::ptrdiff_t>(k), scale.end());
  const double s = std::max(scale[k], 1e-30);
  Ellipsoid e;
  e.center = glm::vec3(center);
  e.radii = glm::vec3(round_up(s * sigma.x), round_up(s * sigma.y), round_up(s * sigma.z));
  return e;
}

TreeProxy derive_shells(const SceneObject& o, const LeafSet& leaves, int shells, uint64_t seed) {
  std::vector<glm::dvec3> points;
  std::vector<double> weights;
  points.reserve(leaves.triangles);
  weights.reserve(leaves.triangles);
  for (size_t t = leaves.first_triangle; t < o.mesh.triangle_count(); ++t) {
    points.push_back(centroid(o, t));
    weights.push_back(triangle_area(o, t));
  }
  const KMeans km = kmeans(points, weights, shells, seed);
  std::vector<double> r2(km.centers.size(), -1.0);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto c = static_cast<size_t>(km.assignment[i]);
    for (int v = 0; v < 3; ++v) {
      const glm::dvec3 q = vertex(o, leaves.first_triangle + i, v) - km.centers[c];
      r2[c] = std::max(r2[c], glm::dot(q, q));
    }
  }
  TreeProxy p;
  p.type = "shells";
  for (size_t c = 0; c < km.centers.size(); ++c)
    if (r2[c] >= 0.0) p.shapes.push_back(sphere_shape(km.centers[c], std::sqrt(r2[c])));
  return p;
}

double shape_volume(const Ellipsoid& e) {
  return 4.0 / 3.0 * kPi * static_cast<double>(e.radii.x) * e.radii.y * e.radii.z;
}

bool contains(const Ellipsoid& e, const glm::dvec3& p) {
  const glm::dvec3 q = glm::transpose(glm::dmat3(e.axes)) * (p - glm::dvec3(e.center));
  const glm::dvec3 u = q / glm::dvec3(e.radii);
  return glm::dot(u, u) <= 1.0;
}

bool proxy_fits(const TreeProxy& p, ProxyKind kind) {
  switch (kind) {
    case ProxyKind::sphere:
      return p.type == "sphere";
    case ProxyKind::ellipsoid:
      return p.type == "sphere" || p.type == "ellipsoid";
    case ProxyKind::shells:
      return p.type == "shells";
  }
  return false;
}

nlohmann::json vec_json(const glm::vec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

const char* proxy_kind_name(ProxyKind kind) {
  switch (kind) {
    case ProxyKind::sphere:
      return "sphere";
    case ProxyKind::ellipsoid:
      return "ellipsoid";
    case ProxyKind::shells:
      return "shells";
  }
  return "?";
}

LeafSet tree_leaves(const SceneObject& o) {
  const size_t n = o.mesh.triangle_count();
  LeafSet s;
  if (auto it = o.facts.find("wood_triangles"); it != o.facts.end()) {
    if (!it->is_number_integer() || it->get<int64_t>() < 0 ||
        static_cast<size_t>(it->get<int64_t>()) > n)
      throw InputError(object_where(o) + ": facts.wood_triangles must be an integer in [0, " +
                       std::to_string(n) + "]");
    s.first_triangle = static_cast<size_t>(it->get<int64_t>());
  }
  s.triangles = n - s.first_triangle;
  for (size_t t = s.first_triangle; t < n; ++t) s.area += triangle_area(o, t);
  if (s.triangles == 0 || !(s.area > 0.0))
    throw InputError(object_where(o) + ": no leaf triangles (facts.wood_triangles = " +
                     std::to_string(s.first_triangle) + " of " + std::to_string(n) +
                     "), so no envelope or leaf density can be derived");
  s.count = static_cast<int64_t>(s.triangles);
  if (auto it = o.facts.find("leaf_count");
      it != o.facts.end() && it->is_number_integer() && it->get<int64_t>() > 0)
    s.count = it->get<int64_t>();
  return s;
}

KMeans kmeans(const std::vector<glm::dvec3>& points, const std::vector<double>& weights, int k,
              uint64_t seed, int max_iterations) {
  KMeans r;
  const size_t n = points.size();
  if (n == 0 || k < 1) return r;
  SplitMix64 rng(mix_seed(seed, 0x4B4D45414E53ull));  // "KMEANS"
  // k-means++: each new centre drawn with probability proportional to weight * squared distance.
  auto draw = [&](const std::vector<double>& mass) -> size_t {
    double total = 0.0;
    for (double m : mass) total += m;
    if (!(total > 0.0)) return n;
    const double u = rng.uniform_double() * total;
    double acc = 0.0;
    for (size_t i = 0; i < n; ++i) {
      acc += mass[i];
      if (u < acc && mass[i] > 0.0) return i;
    }
    for (size_t i = n; i-- > 0;)  // rounding at the very end: the last point with mass
      if (mass[i] > 0.0) return i;
    return n;
  };
  std::vector<double> d2(n, std::numeric_limits<double>::max()), mass(weights);
  while (static_cast<int>(r.centers.size()) < k) {
    const size_t pick = draw(mass);
    if (pick == n) break;  // fewer distinct points than k
    r.centers.push_back(points[pick]);
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 q = points[i] - points[pick];
      d2[i] = std::min(d2[i], glm::dot(q, q));
      mass[i] = weights[i] * d2[i];
    }
  }
  const size_t kk = r.centers.size();
  r.assignment.assign(n, -1);
  for (r.iterations = 1; r.iterations <= max_iterations; ++r.iterations) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      int best = 0;
      double best_d = std::numeric_limits<double>::max();
      for (size_t c = 0; c < kk; ++c) {
        const glm::dvec3 q = points[i] - r.centers[c];
        const double d = glm::dot(q, q);
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(c);
        }
      }
      changed = changed || best != r.assignment[i];
      r.assignment[i] = best;
    }
    if (!changed) break;
    std::vector<glm::dvec3> sum(kk, glm::dvec3(0.0));
    std::vector<double> w(kk, 0.0);
    for (size_t i = 0; i < n; ++i) {
      sum[static_cast<size_t>(r.assignment[i])] += weights[i] * points[i];
      w[static_cast<size_t>(r.assignment[i])] += weights[i];
    }
    for (size_t c = 0; c < kk; ++c)
      if (w[c] > 0.0) r.centers[c] = sum[c] / w[c];
  }
  r.iterations = std::min(r.iterations, max_iterations);
  return r;
}

TreeProxy derive_proxy(const SceneObject& object, const ProxyOptions& options) {
  const LeafSet leaves = tree_leaves(object);
  TreeProxy p;
  p.type = proxy_kind_name(options.kind);
  switch (options.kind) {
    case ProxyKind::sphere: {
      const glm::dvec3 center = leaf_box_center(object, leaves);
      double r2 = 0.0;
      for (size_t t = leaves.first_triangle; t < object.mesh.triangle_count(); ++t)
        for (int c = 0; c < 3; ++c) {
          const glm::dvec3 q = vertex(object, t, c) - center;
          r2 = std::max(r2, glm::dot(q, q));
        }
      p.shapes.push_back(sphere_shape(center, std::sqrt(r2)));
      break;
    }
    case ProxyKind::ellipsoid:
      p.shapes.push_back(derive_ellipsoid(object, leaves, std::clamp(options.coverage, 1e-6, 1.0)));
      break;
    case ProxyKind::shells:
      p = derive_shells(object, leaves, std::max(1, options.shells), options.seed);
      break;
  }
  return p;
}

std::vector<TreeEnvelope> tree_envelopes(const Scene& scene, const ProxyOptions& options,
                                         bool prefer_scene, std::vector<TreeEnvelope>* prototypes) {
  std::vector<TreeEnvelope> out;
  const PlacementIds ids(scene);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    if (o.role != Role::tree) continue;
    TreeEnvelope e;
    e.object = i;
    e.placement = ids.first[i];
    e.leaves = tree_leaves(o);
    e.from_scene = prefer_scene && o.proxy && proxy_fits(*o.proxy, options.kind);
    e.proxy = e.from_scene ? *o.proxy : derive_proxy(o, options);
    const size_t shapes = e.proxy.shapes.size();
    if (o.density) {
      // rho from the scene file (occluders per unit volume) times the mean leaf area.
      const double lambda =
          kLeafProjection * *o.density * e.leaves.area / static_cast<double>(e.leaves.count);
      e.lambda.assign(shapes, lambda);
    } else {
      // The leaf area inside each shape (triangle centroids), so that overlapping shells each see
      // the local density, whatever cluster their leaves came from.
      std::vector<double> area(shapes, 0.0);
      for (size_t t = e.leaves.first_triangle; t < o.mesh.triangle_count(); ++t) {
        const glm::dvec3 c = centroid(o, t);
        const double a = triangle_area(o, t);
        for (size_t s = 0; s < shapes; ++s)
          if (contains(e.proxy.shapes[s], c)) area[s] += a;
      }
      for (size_t s = 0; s < shapes; ++s)
        e.lambda.push_back(kLeafProjection * area[s] / shape_volume(e.proxy.shapes[s]));
    }
    if (o.instances.empty()) {
      out.push_back(std::move(e));
      continue;
    }
    if (prototypes) prototypes->push_back(e);
    for (size_t k = 0; k < o.instances.size(); ++k) {
      const glm::mat4& m = o.instances[k];
      const double s = std::cbrt(std::fabs(static_cast<double>(glm::determinant(glm::mat3(m)))));
      TreeEnvelope placed = e;
      placed.placement = ids.first[i] + k;
      place_proxy(m, placed.proxy);
      placed.leaves.area *= s * s;
      for (double& l : placed.lambda) l *= o.density ? s * s : 1.0 / s;
      out.push_back(std::move(placed));
    }
  }
  return out;
}

nlohmann::json envelope_to_json(const Scene& scene, const TreeEnvelope& e) {
  nlohmann::json shapes = nlohmann::json::array();
  for (const auto& s : e.proxy.shapes)
    shapes.push_back({{"center", vec_json(s.center)}, {"radii", vec_json(s.radii)}});
  const SceneObject& o = scene.objects[e.object];
  const std::string name =
      o.instances.empty()
          ? o.name
          : o.name + "#" + std::to_string(e.placement - PlacementIds(scene).first[e.object]);
  return {{"object", name},
          {"source", e.from_scene ? "scene" : "derived"},
          {"type", e.proxy.type},
          {"shapes", shapes},
          {"lambda", e.lambda},
          {"leaf_area", e.leaves.area},
          {"leaf_count", e.leaves.count}};
}

}  // namespace aoeval
