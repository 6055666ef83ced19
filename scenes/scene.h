// Scenes: the JSON scene format of CONTRACT §4, loaded into world-space triangle meshes with roles,
// tree proxies and named views.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenes/mesh.h"
#include "scenes/sequence.h"

namespace aoeval {

enum class Role { solid, ground, tree, grass };
const char* role_name(Role role);

// An ellipsoid in world space: centre + `axes` (columns, unit length) scaled by `radii`. A sphere
// has equal radii.
struct Ellipsoid {
  glm::vec3 center{0.0f};
  glm::vec3 radii{1.0f};
  glm::mat3 axes{1.0f};
};

// A tree's envelope, as the Hegeman et al. estimators use it: one sphere, one ellipsoid, or several
// spherical shells (their §5).
struct TreeProxy {
  std::string type;  // "sphere", "ellipsoid" or "shells"
  std::vector<Ellipsoid> shapes;
};

struct SceneObject {
  std::string name;
  Role role = Role::solid;
  std::string source;  // "mesh <path>" or "generator <name> seed <k>", for humans
  TriangleMesh mesh;   // world space
  nlohmann::json facts = nlohmann::json::object();  // generator facts, in the generator's own
                                                    // space (before fit and transform)
  std::optional<TreeProxy> proxy;  // from the scene file, world space (prototype space when
                                   // instanced)
  std::optional<double> density;   // from the scene file
  // Diffuse reflectivity (linear RGB), an aoeval extension for the colour-bleeding obscurances of
  // Mendez et al. (their eq. 5-6). Default 0.7 grey.
  glm::vec3 albedo{0.7f};
  // Issue 45 (scenes/instances.h): when non-empty, `mesh` and `proxy` are the prototype, in its own
  // space after the object's fit/transform, and each matrix places one copy of it in the world.
  std::vector<glm::mat4> instances;
  // glTF (scenes/gltf_scene.h): the node each instance is, by name (empty for scene-file objects).
  std::vector<std::string> instance_names;
  // Issue 45 (scenes/stand_on.h): the object this one stands on ("on"), by name; empty = none.
  // Loading has already lifted the placements (or the grass blades) onto it.
  std::string on;
};

// The object's world-space bounds: its mesh's, or the union over its instances of the placed
// corners of the prototype's bounds.
Bounds placed_bounds(const SceneObject& object);

// Applies placement `m` to a proxy's shapes (centres and axes; radii follow the axes' lengths).
void place_proxy(const glm::mat4& m, TreeProxy& proxy);

struct View {
  std::string name;
  glm::vec3 eye{0.0f, 1.0f, 3.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y_deg = 45.0f;
  int width = 320;
  int height = 240;
  // CONTRACT §10: a view that moves over frames; eye and target above are frame 0's camera.
  std::optional<Sequence> sequence;
  int frame_count() const { return sequence ? sequence->frames : 1; }
};

struct Scene {
  std::string name;  // corpus name, or the file's stem
  std::string file;  // path of the scene file
  std::vector<SceneObject> objects;
  std::vector<View> views;

  size_t triangle_count() const;  // unique triangles: an instanced prototype counts once
  Bounds bounds() const;          // world space, every instance included
  // Hash of the world-space geometry and roles: the key of every cache built on this scene.
  uint64_t content_hash() const;
  // The named view, or the first when `name` is empty; InputError naming the known views otherwise.
  const View& view(const std::string& name) const;
};

// Loads a scene file. Mesh paths are relative to the file; a path starting with "cache:" is
// relative to the data cache (see data_cache_dir()). Every error is an InputError naming the file
// and the field. Objects are loaded in parallel; the result does not depend on the thread count.
Scene load_scene_file(const std::string& path);

// The views of a scene file alone, without loading its geometry (for planning sweeps).
std::vector<View> load_scene_views(const std::string& path);

// The cache of computed files (references, compiled shaders): $AOEVAL_CACHE, else
// $XDG_CACHE_HOME/aoeval, else ~/.cache/aoeval.
std::string data_cache_dir();

// Where "cache:REL" mesh paths (the scanned meshes tools/bootstrap.sh extracts from Debian
// packages) are looked for, in order: $AOEVAL_DATA, $AOEVAL_CACHE, then $XDG_CACHE_HOME/aoeval or
// ~/.cache/aoeval. The meshes are set-up data, not computed results: a cluster node given a fresh
// shared AOEVAL_CACHE for its references (issue 19) still finds the meshes its own set-up
// extracted.
std::vector<std::string> mesh_data_dirs();
// The first <dir>/REL of mesh_data_dirs() that exists, else the first candidate (whose loading
// error then names where the mesh was expected).
std::string resolve_cache_mesh(const std::string& rel);

}  // namespace aoeval
