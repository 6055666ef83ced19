#include "scenes/instances.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "base/input_limits.h"
#include "scenes/poisson_disk.h"
#include "scenes/random.h"

namespace aoeval {

glm::mat4 placement_matrix(const glm::vec3& t, const glm::vec3& r, const glm::vec3& s) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), t);
  m = glm::rotate(m, glm::radians(r.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(r.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(r.x), glm::vec3(1, 0, 0));
  return glm::scale(m, s);
}

glm::mat3 placement_normal_matrix(const glm::mat4& m) {
  return glm::transpose(glm::inverse(glm::mat3(m)));
}

void validate_instance(const glm::mat4& m, const Bounds& local, const std::string& where) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]))
        throw InputError(where + ": the transform is not finite (NaN or infinite entries)");
  const glm::dmat3 a = glm::dmat3(glm::mat3(m));
  double lengths = 1.0;
  for (int c = 0; c < 3; ++c) {
    const double l = glm::length(a[c]);
    if (!(l >= 1e-6)) {
      char length[32];
      std::snprintf(length, sizeof length, "%g", l);
      throw InputError(where + ": the transform is singular (an axis is scaled to " + length +
                       ", below 1e-6)");
    }
    lengths *= l;
  }
  if (!(std::fabs(glm::determinant(a)) > 1e-12 * lengths))
    throw InputError(where + ": the transform is singular (its determinant is 0)");
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? local.upper.x : local.lower.x,
                      (corner & 2) ? local.upper.y : local.lower.y,
                      (corner & 4) ? local.upper.z : local.lower.z);
    const glm::dvec3 q = glm::dmat4(m) * glm::dvec4(glm::dvec3(p), 1.0);
    for (int k = 0; k < 3; ++k)
      if (!(std::fabs(q[k]) <= kMaxSceneCoordinate))
        throw InputError(where + ": the placed copy reaches a coordinate beyond " +
                         std::to_string(static_cast<long long>(kMaxSceneCoordinate)));
  }
}

namespace {

// Two numbers [lo, hi] with lo <= hi, each in [min, max].
std::pair<double, double> read_interval(JsonReader& r, const std::string& key,
                                        std::pair<double, double> fallback, double min,
                                        double max) {
  if (!r.has(key)) return fallback;
  const nlohmann::json& v = r.raw(key);
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    r.fail(key, "expected two numbers [lo, hi]");
  const double lo = v[0].get<double>(), hi = v[1].get<double>();
  if (!(lo >= min && hi <= max && lo <= hi))
    r.fail(key,
           "expected lo <= hi within [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  return {lo, hi};
}

// The placers (README "Instanced objects"): `count` spots over a width x depth rectangle of the
// y = center.y plane, on a jittered grid (one per cell at a seeded spot) or Poisson-disk (seeded
// dart throwing, no two closer than `spacing` x sqrt(area / count)); each spot is dealt to K
// prototypes by a seeded hash and this object takes the spots of share k.
std::vector<glm::mat4> placer(JsonReader& p, const std::string& kind) {
  const auto seed = static_cast<uint64_t>(p.integer("seed", 1, 0, INT64_MAX));
  const auto count =
      static_cast<size_t>(p.integer("count", 1, static_cast<int64_t>(kMaxInstances)));
  const glm::vec3 center = p.vec3("center", glm::vec3(0.0f));
  std::pair<double, double> size{10.0, 10.0};
  if (p.has("size")) {
    const nlohmann::json& v = p.raw("size");
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number() ||
        !(v[0].get<double>() > 0.0 && v[1].get<double>() > 0.0 &&
          v[0].get<double>() <= 2.0 * kMaxSceneCoordinate &&
          v[1].get<double>() <= 2.0 * kMaxSceneCoordinate))
      p.fail("size", "expected two positive numbers [width, depth]");
    size = {v[0].get<double>(), v[1].get<double>()};
  }
  const auto share = read_interval(p, "share", {0.0, 1.0}, 0.0, 1e6);
  const auto k = static_cast<uint64_t>(share.first), shares = static_cast<uint64_t>(share.second);
  if (share.first != static_cast<double>(k) || share.second != static_cast<double>(shares) ||
      k >= shares)
    p.fail("share", "expected two integers [k, K] with 0 <= k < K");
  const auto scale = read_interval(p, "scale", {1.0, 1.0}, 1e-6, 1e6);
  const auto rotate = read_interval(p, "rotate_y_deg", {0.0, 360.0}, -1e4, 1e4);
  const bool grid = kind == "jittered-grid";
  const double jitter = grid ? p.number("jitter", 0.8, 0.0, 1.0) : 0.0;
  const double spacing = grid ? 0.0 : p.number("spacing", 0.7, 1e-3, kMaxPoissonSpacing);
  p.finish();
  const double width = size.first, depth = size.second;
  const auto nx = static_cast<size_t>(
      std::max(1.0, std::ceil(std::sqrt(static_cast<double>(count) * width / depth))));
  const double cell_w = width / static_cast<double>(nx);
  const double cell_d = depth / std::ceil(static_cast<double>(count) / static_cast<double>(nx));
  std::vector<glm::dvec2> disk;
  if (!grid) {
    auto points = poisson_disk_points(seed, count, width, depth, spacing);
    if (!points)
      p.fail("spacing", "cannot place " + std::to_string(count) + " points at this spacing in " +
                            std::to_string(64 * count) + " darts; lower it");
    disk = std::move(*points);
  }
  std::vector<glm::mat4> out;
  for (size_t c = 0; c < count; ++c) {
    SplitMix64 g(mix_seed(seed, c, 0x4E5));
    if (g.next() % shares != k) continue;
    double x = 0.0, z = 0.0;
    if (grid) {
      const double u = 0.5 + jitter * (g.uniform_double() - 0.5);
      const double v = 0.5 + jitter * (g.uniform_double() - 0.5);
      x = (static_cast<double>(c % nx) + u) * cell_w;
      z = (static_cast<double>(c / nx) + v) * cell_d;
    } else {
      x = disk[c].x;
      z = disk[c].y;
    }
    x += center.x - 0.5 * width;
    z += center.z - 0.5 * depth;
    const double s = scale.first + (scale.second - scale.first) * g.uniform_double();
    const double ry = rotate.first + (rotate.second - rotate.first) * g.uniform_double();
    out.push_back(placement_matrix(
        glm::vec3(static_cast<float>(x), center.y, static_cast<float>(z)),
        glm::vec3(0.0f, static_cast<float>(ry), 0.0f), glm::vec3(static_cast<float>(s))));
  }
  return out;
}

}  // namespace

std::vector<glm::mat4> read_instances(JsonReader& object, const Bounds& local) {
  std::vector<glm::mat4> out;
  const nlohmann::json& raw = object.json().at("instances");
  if (raw.is_object()) {
    JsonReader p = object.object("instances");
    const std::string kind = p.choice("placer", "jittered-grid", {"jittered-grid", "poisson-disk"});
    out = placer(p, kind);
  } else {
    if (!raw.is_array())
      object.fail("instances", "expected an array of transforms or a placer object");
    if (raw.size() > kMaxInstances)
      object.fail("instances", std::to_string(raw.size()) + " instances exceed the limit of " +
                                   std::to_string(kMaxInstances));
    for (auto& t : object.array_of_objects("instances", 1)) {
      const glm::vec3 tr = t.vec3("translate", glm::vec3(0.0f));
      const glm::vec3 r = t.vec3("rotate_deg", glm::vec3(0.0f));
      const glm::vec3 s = t.vec3("scale", glm::vec3(1.0f));
      t.finish();
      out.push_back(placement_matrix(tr, r, s));
    }
  }
  for (size_t i = 0; i < out.size(); ++i)
    validate_instance(
        out[i], local,
        object.file() + ": " + object.where("instances") + "[" + std::to_string(i) + "]");
  return out;
}

PlacementIds::PlacementIds(const Scene& scene) {
  first.reserve(scene.objects.size());
  for (const auto& o : scene.objects) {
    first.push_back(count);
    count += o.instances.empty() ? 1 : o.instances.size();
  }
}

size_t PlacementIds::object_of(size_t id) const {
  if (id >= count) return first.size();
  return static_cast<size_t>(std::upper_bound(first.begin(), first.end(), id) - first.begin()) - 1;
}

bool has_instances(const Scene& scene) {
  return std::any_of(scene.objects.begin(), scene.objects.end(),
                     [](const SceneObject& o) { return !o.instances.empty(); });
}

size_t instanced_triangle_count(const Scene& scene) {
  size_t n = 0;
  for (const auto& o : scene.objects)
    n += o.mesh.triangle_count() * std::max<size_t>(1, o.instances.size());
  return n;
}

size_t instance_count(const Scene& scene) {
  size_t n = 0;
  for (const auto& o : scene.objects) n += o.instances.size();
  return n;
}

double estimated_bytes(const Scene& scene, bool as_copies) {
  const double triangles =
      static_cast<double>(as_copies ? instanced_triangle_count(scene) : scene.triangle_count());
  const double instances = as_copies ? 0.0 : static_cast<double>(instance_count(scene));
  return triangles * static_cast<double>(kBytesPerTriangleBudget) +
         instances * static_cast<double>(kBytesPerInstanceBudget);
}

void check_scene_memory(const Scene& scene, double bytes, size_t available,
                        const std::string& what) {
  if (available == 0 || bytes <= static_cast<double>(available)) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char numbers[200];
  std::snprintf(numbers, sizeof numbers,
                "needs about %.1f GiB of memory (%zu bytes per triangle, %zu per instance); this "
                "machine has %.1f GiB available",
                bytes / kGiB, kBytesPerTriangleBudget, kBytesPerInstanceBudget,
                static_cast<double>(available) / kGiB);
  throw InputError("scene '" + scene.name + "': " + what + " (" +
                   std::to_string(instanced_triangle_count(scene)) + " triangles as placed) " +
                   numbers);
}

Scene scene_as_copies(const Scene& scene) {
  check_scene_memory(scene, estimated_bytes(scene, true), available_memory_bytes(),
                     "the scene written out as copies");
  Scene out;
  out.name = scene.name;
  out.file = scene.file;
  out.views = scene.views;
  for (const auto& o : scene.objects) {
    if (o.instances.empty()) {
      out.objects.push_back(o);
      continue;
    }
    for (size_t i = 0; i < o.instances.size(); ++i) {
      const glm::mat4& m = o.instances[i];
      SceneObject c;
      c.name = i < o.instance_names.size() ? o.instance_names[i] : o.name + "#" + std::to_string(i);
      c.role = o.role;
      c.source = o.source + " instance " + std::to_string(i);
      c.facts = o.facts;
      c.density = o.density;
      c.albedo = o.albedo;
      c.mesh = o.mesh;
      const glm::mat3 nm = placement_normal_matrix(m);
      for (auto& v : c.mesh.positions) v = place_point(m, v);
      for (auto& n : c.mesh.normals) n = glm::normalize(nm * n);
      if (glm::determinant(glm::mat3(m)) < 0.0f)
        for (auto& t : c.mesh.triangles) std::swap(t.y, t.z);
      if (o.proxy) {
        c.proxy = o.proxy;
        place_proxy(m, *c.proxy);
      }
      out.objects.push_back(std::move(c));
    }
  }
  return out;
}

void refuse_instances(const Scene& scene, const std::string& consumer) {
  for (const auto& o : scene.objects)
    if (!o.instances.empty())
      throw InputError("scene '" + scene.name + "': object '" + o.name + "' is instanced (" +
                       std::to_string(o.instances.size()) + " instances); " + consumer +
                       " reads world-space copies and does not take instanced objects");
}

}  // namespace aoeval
