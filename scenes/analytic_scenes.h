// Building blocks for analytic test scenes (pbrt-style tests with known answers): objects from the
// generators placed in world space, a scene of them, and "probes" — G-buffers whose pixels all sit
// at one chosen surface point, so that many independent pixels pool into one precise estimate.
#pragma once

#include <string>
#include <vector>

#include "scenes/gbuffer.h"
#include "scenes/generators/generators.h"
#include "scenes/scene.h"

namespace aoeval {

// A generator's mesh, translated, with its facts and an albedo.
inline SceneObject generated(const std::string& name, const std::string& generator,
                             nlohmann::json params, glm::vec3 translate = glm::vec3(0.0f),
                             glm::vec3 albedo = glm::vec3(0.7f)) {
  JsonReader reader(params, "test");
  GeneratedGeometry geometry = find_generator(generator)->function(1, reader);
  reader.finish();
  SceneObject o;
  o.name = name;
  o.mesh = std::move(geometry.mesh);
  o.facts = std::move(geometry.facts);
  o.albedo = albedo;
  for (auto& p : o.mesh.positions) p += translate;
  return o;
}

inline Scene scene_of(std::vector<SceneObject> objects) {
  Scene s;
  s.name = "analytic";
  s.objects = std::move(objects);
  s.views.push_back(View{});
  return s;
}

// A G-buffer of `count` pixels, all at surface point p with normal n (object 0).
inline GBuffer probe(glm::vec3 p, glm::vec3 n, int count) {
  GBuffer g;
  g.width = count;
  g.height = 1;
  g.coverage.assign(count, 1.0f);
  g.depth.assign(count, 1.0f);
  g.position.assign(count, p);
  g.normal.assign(count, n);
  g.geometric_normal.assign(count, n);
  g.object_id.assign(count, 0.0f);
  return g;
}

}  // namespace aoeval
