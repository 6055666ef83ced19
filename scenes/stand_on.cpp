#include "scenes/stand_on.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

#include "base/errors.h"
#include "scenes/instances.h"
#include "scenes/surface_height.h"

namespace aoeval {
namespace {

std::string spot_text(double x, double z) {
  char text[80];
  std::snprintf(text, sizeof text, "(x %g, z %g)", x, z);
  return text;
}

float height_at(const SurfaceHeight& surface, double x, double z, const std::string& where,
                const std::string& on) {
  const auto p = surface.at(x, z);
  if (!p)
    throw InputError(where + ": the spot " + spot_text(x, z) + " lies outside object '" + on +
                     "' seen from above");
  return p->y;
}

// The grass generator's layout: vertices per blade and blades; {0, 0} when the mesh is not it.
std::pair<size_t, size_t> blade_layout(const SceneObject& o) {
  const auto& f = o.facts;
  if (!f.contains("segments") || !f.contains("blade_count")) return {0, 0};
  const size_t stride = 2 * f["segments"].get<size_t>() + 1;
  const size_t blades = f["blade_count"].get<size_t>();
  if (blades * stride != o.mesh.positions.size()) return {0, 0};
  return {stride, blades};
}

void lift_grass(SceneObject& o, const SurfaceHeight& surface, const std::string& where) {
  const auto [stride, blades] = blade_layout(o);
  if (stride == 0)
    throw InputError(where + ": the grass field's vertices are not the grass generator's blades");
  for (size_t b = 0; b < blades; ++b) {
    glm::vec3* v = &o.mesh.positions[b * stride];
    const double x = 0.5 * (static_cast<double>(v[0].x) + v[1].x);
    const double z = 0.5 * (static_cast<double>(v[0].z) + v[1].z);
    const float h = height_at(surface, x, z, where + " blade " + std::to_string(b), o.on);
    for (size_t k = 0; k < stride; ++k) v[k].y += h;
  }
  validate_mesh(o.mesh, where);
}

}  // namespace

std::optional<float> grass_blade_height(const SceneObject& grass) {
  const auto [stride, blades] = blade_layout(grass);
  if (stride == 0) return std::nullopt;
  float h = 0.0f;
  for (size_t b = 0; b < blades; ++b) {
    const glm::vec3* v = &grass.mesh.positions[b * stride];
    h = std::max(h, v[stride - 1].y - 0.5f * (v[0].y + v[1].y));
  }
  return h;
}

void stand_on_surfaces(Scene& scene) {
  std::map<std::string, size_t> by_name;
  for (size_t i = 0; i < scene.objects.size(); ++i) by_name[scene.objects[i].name] = i;
  std::map<size_t, std::unique_ptr<SurfaceHeight>> surfaces;
  for (auto& o : scene.objects) {
    if (o.on.empty()) continue;
    const std::string where = scene.file + ": object '" + o.name + "', on '" + o.on + "'";
    const auto it = by_name.find(o.on);
    if (it == by_name.end()) throw InputError(where + ": no object of that name");
    const SceneObject& ground = scene.objects[it->second];
    if (!ground.instances.empty() || !ground.on.empty())
      throw InputError(where + ": it is instanced or stands on another object itself");
    auto& surface = surfaces[it->second];
    if (!surface) surface = std::make_unique<SurfaceHeight>(ground.mesh);
    if (o.instances.empty()) {
      lift_grass(o, *surface, where);
      continue;
    }
    const Bounds local = o.mesh.bounds();
    for (size_t k = 0; k < o.instances.size(); ++k) {
      glm::mat4& m = o.instances[k];
      const std::string spot = where + ": instances[" + std::to_string(k) + "]";
      m[3].y += height_at(*surface, m[3].x, m[3].z, spot, o.on);
      validate_instance(m, local, spot);
    }
  }
}

}  // namespace aoeval
