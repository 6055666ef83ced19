#include "scenes/scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "base/hash.h"
#include "base/json_reader.h"
#include "scenes/generators/generators.h"
#include "scenes/gltf_scene.h"
#include "scenes/instances.h"
#include "scenes/mesh_io.h"
#include "scenes/stand_on.h"

namespace aoeval {

namespace fs = std::filesystem;

const char* role_name(Role role) {
  switch (role) {
    case Role::solid:
      return "solid";
    case Role::ground:
      return "ground";
    case Role::tree:
      return "tree";
    case Role::grass:
      return "grass";
  }
  return "solid";
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const auto& o : objects) n += o.mesh.triangle_count();
  return n;
}

Bounds Scene::bounds() const {
  Bounds b;
  for (const auto& o : objects) b.extend(placed_bounds(o));
  return b;
}

Bounds placed_bounds(const SceneObject& o) {
  const Bounds local = o.mesh.bounds();
  if (o.instances.empty()) return local;
  Bounds b;
  for (const glm::mat4& m : o.instances)
    for (int corner = 0; corner < 8; ++corner)
      b.extend(place_point(m, glm::vec3((corner & 1) ? local.upper.x : local.lower.x,
                                        (corner & 2) ? local.upper.y : local.lower.y,
                                        (corner & 4) ? local.upper.z : local.lower.z)));
  return b;
}

uint64_t Scene::content_hash() const {
  uint64_t h = 0x84222325cbf29ce4ull;
  for (const auto& o : objects) {
    h = fnv1a_fold(h, aoeval::content_hash(o.mesh));
    h = fnv1a_fold(h, static_cast<uint64_t>(o.role));
    // Only instanced objects fold in their placements, so every other scene keeps its hash.
    if (!o.instances.empty()) {
      Fnv1a f;
      f.bytes(o.instances.data(), o.instances.size() * sizeof(glm::mat4));
      h = fnv1a_fold(h, f.h);
    }
  }
  return h;
}

const View& Scene::view(const std::string& view_name) const {
  if (view_name.empty()) return views.front();
  std::string known;
  for (const auto& v : views) {
    if (v.name == view_name) return v;
    known += (known.empty() ? "" : ", ") + v.name;
  }
  throw InputError(file + ": views: no view named '" + view_name + "' (views: " + known + ")");
}

std::string data_cache_dir() {
  if (const char* c = std::getenv("AOEVAL_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/aoeval";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/aoeval";
  return ".aoeval-cache";
}

std::vector<std::string> mesh_data_dirs() {
  std::vector<std::string> dirs;
  auto add = [&dirs](const std::string& d) {
    if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
  };
  if (const char* d = std::getenv("AOEVAL_DATA"); d && *d) add(d);
  if (const char* c = std::getenv("AOEVAL_CACHE"); c && *c) add(c);
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    add(std::string(x) + "/aoeval");
  else if (const char* h = std::getenv("HOME"); h && *h)
    add(std::string(h) + "/.cache/aoeval");
  if (dirs.empty()) add(".aoeval-cache");
  return dirs;
}

std::string resolve_cache_mesh(const std::string& rel) {
  const std::vector<std::string> dirs = mesh_data_dirs();
  for (const auto& d : dirs) {
    std::error_code ec;
    const fs::path p = fs::path(d) / rel;
    if (fs::exists(p, ec)) return p.string();
  }
  return (fs::path(dirs.front()) / rel).string();
}

namespace {

// The object's placement: optional "fit" (uniform scale to a size, resting on y = 0 or centred at
// the origin) applied first, then scale, rotation (X, then Y, then Z, degrees) and translation.
struct Placement {
  glm::mat4 matrix{1.0f};
  glm::mat3 normal_matrix{1.0f};
};

Placement read_placement(JsonReader& object, const Bounds& local_bounds) {
  glm::mat4 fit(1.0f);
  if (auto f = object.optional_object("fit")) {
    float size = static_cast<float>(f->number("size", 1e-6, 1e6));
    bool on_ground = f->boolean("on_ground", true);
    f->finish();
    glm::vec3 ext = local_bounds.extent();
    float largest = std::max(ext.x, std::max(ext.y, ext.z));
    if (!(largest > 0.0f)) object.fail("fit", "cannot fit a mesh of zero extent");
    glm::vec3 anchor = local_bounds.center();
    if (on_ground) anchor.y = local_bounds.lower.y;
    fit = glm::scale(glm::mat4(1.0f), glm::vec3(size / largest)) *
          glm::translate(glm::mat4(1.0f), -anchor);
  }
  glm::vec3 t(0.0f), r(0.0f), s(1.0f);
  if (auto tr = object.optional_object("transform")) {
    t = tr->vec3("translate", t);
    r = tr->vec3("rotate_deg", r);
    s = tr->vec3("scale", s);
    for (int i = 0; i < 3; ++i)
      if (s[i] == 0.0f) tr->fail("scale", "scale components must be non-zero");
    tr->finish();
  }
  const glm::mat4 m = placement_matrix(t, r, s);
  Placement p;
  p.matrix = m * fit;
  p.normal_matrix = glm::transpose(glm::inverse(glm::mat3(p.matrix)));
  return p;
}

void apply(const Placement& p, TriangleMesh& mesh) {
  for (auto& v : mesh.positions) v = glm::vec3(p.matrix * glm::vec4(v, 1.0f));
  for (auto& n : mesh.normals) n = glm::normalize(p.normal_matrix * n);
  // A mirroring transform flips the winding; restore counter-clockwise = front.
  if (glm::determinant(glm::mat3(p.matrix)) < 0.0f)
    for (auto& t : mesh.triangles) std::swap(t.y, t.z);
}

Ellipsoid read_ellipsoid(JsonReader& r, bool sphere) {
  Ellipsoid e;
  e.center = r.vec3("center");
  if (sphere) {
    e.radii = glm::vec3(static_cast<float>(r.number("radius", 1e-6, 1e6)));
  } else {
    e.radii = r.vec3("radii");
    for (int i = 0; i < 3; ++i)
      if (!(e.radii[i] > 0.0f)) r.fail("radii", "radii must be positive");
  }
  r.finish();
  return e;
}

TreeProxy read_proxy(JsonReader r) {
  TreeProxy proxy;
  proxy.type = r.choice("type", "sphere", {"sphere", "ellipsoid", "shells"});
  if (proxy.type == "shells") {
    for (auto& s : r.array_of_objects("shells", 1)) proxy.shapes.push_back(read_ellipsoid(s, true));
    r.finish();
  } else {
    proxy.shapes.push_back(read_ellipsoid(r, proxy.type == "sphere"));
  }
  return proxy;
}

}  // namespace

void place_proxy(const glm::mat4& m, TreeProxy& proxy) {
  glm::mat3 linear(m);
  for (auto& e : proxy.shapes) {
    e.center = glm::vec3(m * glm::vec4(e.center, 1.0f));
    for (int a = 0; a < 3; ++a) {
      glm::vec3 axis = linear * (e.axes[a] * e.radii[a]);
      e.radii[a] = glm::length(axis);
      e.axes[a] = axis / e.radii[a];
    }
  }
}

namespace {

// A {"name": N, "gltf": path} entry: the file's mesh nodes as objects "N/<node>" (README "glTF
// scenes"), with the entry's role and albedo, and its "fit"/"transform" applied to them all.
std::vector<SceneObject> load_gltf_entry(JsonReader& reader, const fs::path& scene_dir) {
  const std::string name = reader.string("name");
  const std::string rel = reader.string("gltf");
  const std::string role = reader.choice("role", "solid", {"solid", "ground"});
  const bool instanced =
      reader.choice("shared_meshes", "instanced", {"instanced", "copies"}) == "instanced";
  const glm::vec3 albedo = reader.vec3("albedo", glm::vec3(0.7f));
  for (int c = 0; c < 3; ++c)
    if (albedo[c] < 0.0f || albedo[c] > 1.0f) reader.fail("albedo", "components must be in [0, 1]");
  const fs::path path =
      rel.rfind("cache:", 0) == 0 ? fs::path(resolve_cache_mesh(rel.substr(6))) : scene_dir / rel;
  std::vector<SceneObject> objects;
  try {
    objects = load_gltf_objects(path.string(), name + "/", instanced);
  } catch (const InputError& e) {
    reader.fail("gltf", e.what());
  }
  if (objects.empty()) reader.fail("gltf", path.string() + ": no mesh node");
  Bounds all;
  for (const auto& o : objects) all.extend(placed_bounds(o));
  const Placement placement = read_placement(reader, all);
  for (auto& o : objects) {
    o.role = role == "ground" ? Role::ground : Role::solid;
    o.albedo = albedo;
    if (o.instances.empty()) {
      apply(placement, o.mesh);
      validate_mesh(o.mesh, reader.file() + ": " + reader.where("gltf") + " (placed)");
    } else {
      for (auto& m : o.instances) {
        m = placement.matrix * m;
        validate_instance(m, o.mesh.bounds(), reader.file() + ": " + reader.where("gltf"));
      }
    }
  }
  reader.finish();
  return objects;
}

// Reads one object; `reader` is consumed. Runs on a worker thread.
SceneObject load_object(JsonReader reader, const fs::path& scene_dir) {
  SceneObject obj;
  obj.name = reader.string("name");
  std::string role = reader.choice("role", "solid", {"solid", "ground", "tree", "grass"});
  obj.role = role == "ground"  ? Role::ground
             : role == "tree"  ? Role::tree
             : role == "grass" ? Role::grass
                               : Role::solid;
  const bool has_mesh = reader.has("mesh"), has_gen = reader.has("generator");
  if (has_mesh == has_gen)
    reader.fail("", "an object needs exactly one of \"mesh\" or \"generator\"");
  if (has_mesh) {
    std::string rel = reader.string("mesh");
    fs::path path =
        rel.rfind("cache:", 0) == 0 ? fs::path(resolve_cache_mesh(rel.substr(6))) : scene_dir / rel;
    obj.source = "mesh " + path.string();
    try {
      obj.mesh = load_mesh(path.string());
    } catch (const InputError& e) {
      reader.fail("mesh", e.what());
    }
  } else {
    std::string gen = reader.string("generator");
    const GeneratorInfo* info = find_generator(gen);
    if (!info) {
      std::string known;
      for (const auto& g : generator_registry())
        known += (known.empty() ? "" : ", ") + std::string(g.name);
      reader.fail("generator", "unknown generator '" + gen + "' (known: " + known + ")");
    }
    auto seed = static_cast<uint64_t>(reader.integer("seed", 1, 0, INT64_MAX));
    obj.source = "generator " + gen + " seed " + std::to_string(seed);
    nlohmann::json empty = nlohmann::json::object();
    JsonReader params = reader.has("params")
                            ? reader.object("params")
                            : JsonReader(empty, reader.file(), reader.where("params"));
    GeneratedGeometry g = info->function(seed, params);
    params.finish();
    validate_mesh(g.mesh, reader.file() + ": " + reader.where("generator"));
    obj.mesh = std::move(g.mesh);
    obj.facts = std::move(g.facts);
  }
  Placement placement = read_placement(reader, obj.mesh.bounds());
  apply(placement, obj.mesh);
  // The placed vertices are checked again: a translate, scale or fit that is valid on its own can
  // still carry a vertex past float's range or the coordinate limit (input_limits.h).
  if (reader.has("transform") || reader.has("fit"))
    validate_mesh(obj.mesh, reader.file() + ": " +
                                reader.where(reader.has("transform") ? "transform" : "fit"));
  if (auto p = reader.optional_object("proxy")) {
    if (obj.role != Role::tree)
      reader.fail("proxy", "only objects with role \"tree\" take a proxy");
    obj.proxy = read_proxy(*p);
    place_proxy(placement.matrix, *obj.proxy);
  }
  if (reader.has("instances")) obj.instances = read_instances(reader, obj.mesh.bounds());
  if (reader.has("on")) {
    obj.on = reader.string("on");
    if (!reader.has("instances") &&
        !(obj.role == Role::grass && obj.source.starts_with("generator grass ")))
      reader.fail("on",
                  "only instanced objects and grass fields of the grass generator stand on "
                  "another object");
    if (obj.on == obj.name) reader.fail("on", "an object cannot stand on itself");
  }
  obj.albedo = reader.vec3("albedo", obj.albedo);
  for (int c = 0; c < 3; ++c)
    if (obj.albedo[c] < 0.0f || obj.albedo[c] > 1.0f)
      reader.fail("albedo", "components must be in [0, 1]");
  if (reader.has("density")) {
    if (obj.role != Role::tree)
      reader.fail("density", "only objects with role \"tree\" take a density");
    obj.density = reader.number("density", 1e-9, 1e12);
  }
  reader.finish();
  return obj;
}

// Why the camera at `eye` looking at `target` with `up` has no viewing basis ("" when it has
// one). Checked in double precision: in float, |target - eye|^2 overflows for eyes near 1e20 and
// a zero `up` gives a zero cross product that passed a relative test, and either made NaN rays
// that Embree rejects with an assertion.
std::string camera_basis_problem(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up) {
  const glm::dvec3 fwd = target - eye;
  const double fwd_length = glm::length(fwd), up_length = glm::length(up);
  if (!(fwd_length > 1e-6)) return "eye and target coincide";
  if (!(up_length > 0.0)) return "up must not be the zero vector";
  if (!(glm::length(glm::cross(fwd / fwd_length, up / up_length)) > 1e-6))
    return "up is parallel to the viewing direction";
  return "";
}

std::string vec3_text(glm::vec3 v) {
  char text[96];
  std::snprintf(text, sizeof text, "[%g, %g, %g]", static_cast<double>(v.x),
                static_cast<double>(v.y), static_cast<double>(v.z));
  return text;
}

// Every frame's camera of a sequence view, as sequence_frame.cpp will build it (camera_at, linear
// between keys): a path that passes through its target or looks along `up` between two good keys
// would otherwise load, render frame 0 and stop a sweep at that frame.
void check_sequence_cameras(const View& v, const JsonReader& r) {
  for (int k = 1; k < v.sequence->frames; ++k) {
    const CameraKey c = camera_at(*v.sequence, v.eye, v.target, k);
    const std::string problem = camera_basis_problem(c.eye, c.target, v.up);
    if (!problem.empty())
      r.fail("sequence.camera", "view '" + v.name + "', frame " + std::to_string(k) +
                                    " (between the keys): " + problem + " (eye " +
                                    vec3_text(c.eye) + ", target " + vec3_text(c.target) + ", up " +
                                    vec3_text(v.up) + ")");
  }
}

View read_view(JsonReader r) {
  View v;
  v.name = r.string("name");
  v.eye = r.vec3("eye");
  v.target = r.vec3("target");
  v.up = r.vec3("up", v.up);
  v.fov_y_deg = static_cast<float>(r.number("fov_y_deg", 45.0, 1.0, 170.0));
  v.width = static_cast<int>(r.integer("width", 320, 1, 16384));
  v.height = static_cast<int>(r.integer("height", 240, 1, 16384));
  const std::string problem = camera_basis_problem(v.eye, v.target, v.up);
  if (!problem.empty()) r.fail(problem.starts_with("eye") ? "target" : "up", problem);
  if (auto seq = r.optional_object("sequence")) {
    v.sequence = read_sequence(*seq, v.eye, v.target);
    check_sequence_cameras(v, r);
  }
  r.finish();
  return v;
}

}  // namespace

std::vector<View> load_scene_views(const std::string& path) {
  if (is_gltf_path(path)) return load_gltf_scene(path).views;
  nlohmann::json doc = parse_json_file(path);
  JsonReader root(doc, path);
  std::vector<std::string> object_names;
  const nlohmann::json& objects = root.raw("objects");
  if (objects.is_array())
    for (const auto& o : objects)
      if (o.is_object() && o.contains("name") && o["name"].is_string())
        object_names.push_back(o["name"].get<std::string>());
  std::vector<View> views;
  for (auto& v : root.array_of_objects("views", 1)) views.push_back(read_view(v));
  // A glTF entry's object names ("N/<node>") are known only once its file is read.
  const bool has_gltf = objects.is_array() &&
                        std::any_of(objects.begin(), objects.end(),
                                    [](auto& o) { return o.is_object() && o.contains("gltf"); });
  for (const auto& v : views)
    if (v.sequence && !has_gltf) check_sequence_objects(*v.sequence, object_names, path, v.name);
  return views;
}

Scene load_scene_file(const std::string& path) {
  if (is_gltf_path(path)) return load_gltf_scene(path);
  nlohmann::json doc = parse_json_file(path);
  JsonReader root(doc, path);
  Scene scene;
  scene.file = path;
  scene.name = fs::path(path).stem().string();
  auto object_readers = root.array_of_objects("objects", 1);
  for (auto& v : root.array_of_objects("views", 1)) scene.views.push_back(read_view(v));
  root.finish();
  for (size_t i = 0; i < scene.views.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (scene.views[i].name == scene.views[j].name)
        throw InputError(path + ": views[" + std::to_string(i) + "].name: duplicate view name '" +
                         scene.views[i].name + "'");

  const fs::path dir = fs::path(path).parent_path();
  std::vector<std::vector<SceneObject>> loaded(object_readers.size());
  std::vector<std::exception_ptr> errors(object_readers.size());
  tbb::parallel_for(size_t(0), object_readers.size(), [&](size_t i) {
    try {
      if (object_readers[i].has("gltf"))
        loaded[i] = load_gltf_entry(object_readers[i], dir);
      else
        loaded[i].push_back(load_object(object_readers[i], dir));
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const auto& e : errors)  // report the first failing object, in file order
    if (e) std::rethrow_exception(e);
  // An object placed by "instances" whose placer gave it no spot (a share of a small count: the
  // spots go to the shares by a seeded hash) has no copy: it is left out, not drawn once as a
  // plain object at its own transform.
  for (size_t i = 0; i < loaded.size(); ++i)
    for (auto& o : loaded[i])
      if (!(object_readers[i].has("instances") && o.instances.empty()))
        scene.objects.push_back(std::move(o));
  for (size_t i = 0; i < scene.objects.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (scene.objects[i].name == scene.objects[j].name)
        throw InputError(path + ": objects[" + std::to_string(i) +
                         "].name: duplicate object name '" + scene.objects[i].name + "'");
  stand_on_surfaces(scene);
  if (instance_count(scene) > kMaxInstances)
    throw InputError(path + ": objects: " + std::to_string(instance_count(scene)) +
                     " instances in all exceed the limit of " + std::to_string(kMaxInstances));
  std::vector<std::string> object_names;
  for (const auto& o : scene.objects) object_names.push_back(o.name);
  for (const auto& v : scene.views)
    if (v.sequence) check_sequence_objects(*v.sequence, object_names, path, v.name);
  return scene;
}

}  // namespace aoeval
