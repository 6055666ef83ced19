#include "scenes/gltf_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <map>
#include <set>

#include "base/errors.h"
#include "scenes/embree_scene.h"
#include "scenes/gltf_animation.h"
#include "scenes/gltf_document.h"
#include "scenes/instances.h"

namespace aoeval {

namespace fs = std::filesystem;

bool is_gltf_path(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".glb" || ext == ".gltf";
}

namespace {

// Mesh `m` in its own space: every primitive's triangles, normals when every primitive has them.
TriangleMesh read_mesh(const GltfDocument& doc, size_t m) {
  const std::string at = "meshes[" + std::to_string(m) + "]";
  const nlohmann::json& mesh = doc.array("meshes")[m];
  if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
    doc.fail(at, "a mesh needs primitives");
  TriangleMesh out;
  bool all_normals = true;
  std::vector<TriangleMesh> parts;
  for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
    const std::string pat = at + ".primitives[" + std::to_string(p) + "]";
    const nlohmann::json& prim = mesh["primitives"][p];
    const int mode = prim.value("mode", 4);
    if (mode != 4)
      doc.fail(pat + ".mode", "mode " + std::to_string(mode) +
                                  " is not triangles (4); aoeval reads triangle primitives only");
    if (!prim.contains("attributes") || !prim["attributes"].contains("POSITION"))
      doc.fail(pat + ".attributes", "a primitive needs POSITION");
    const nlohmann::json& attributes = prim["attributes"];
    TriangleMesh part;
    const std::vector<float> xyz =
        doc.floats(attributes["POSITION"], "VEC3", pat + ".attributes.POSITION");
    for (size_t i = 0; i + 2 < xyz.size(); i += 3)
      part.positions.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
    if (attributes.contains("NORMAL")) {
      const std::vector<float> n =
          doc.floats(attributes["NORMAL"], "VEC3", pat + ".attributes.NORMAL");
      if (n.size() != xyz.size()) doc.fail(pat + ".attributes.NORMAL", "not one per position");
      for (size_t i = 0; i + 2 < n.size(); i += 3) {
        const glm::vec3 v(n[i], n[i + 1], n[i + 2]);
        const float len = glm::length(v);
        part.normals.push_back(len > 0.0f ? v / len : glm::vec3(0.0f, 1.0f, 0.0f));
      }
    } else {
      all_normals = false;
    }
    std::vector<uint32_t> idx;
    if (prim.contains("indices")) {
      idx = doc.indices(prim["indices"], pat + ".indices");
    } else {
      idx.resize(part.positions.size());
      for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<uint32_t>(i);
    }
    if (idx.size() % 3 != 0)
      doc.fail(pat + ".indices", std::to_string(idx.size()) + " indices are not whole triangles");
    for (size_t i = 0; i < idx.size(); i += 3) {
      for (size_t c = 0; c < 3; ++c)
        if (idx[i + c] >= part.positions.size())
          doc.fail(pat + ".indices", "index " + std::to_string(idx[i + c]) + " of " +
                                         std::to_string(part.positions.size()) + " vertices");
      part.triangles.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
    }
    parts.push_back(std::move(part));
  }
  for (auto& part : parts) {
    if (!all_normals) part.normals.clear();
    out.append(part);
  }
  validate_mesh(out, doc.file() + ": " + at);
  if (!all_normals) compute_vertex_normals(out);
  return out;
}

glm::mat4 to_float(const glm::dmat4& m) {
  return glm::mat4(m);
}

void place(const glm::mat4& m, TriangleMesh& mesh) {
  const glm::mat3 nm = glm::inverseTranspose(glm::mat3(m));
  for (auto& v : mesh.positions) v = place_point(m, v);
  for (auto& n : mesh.normals) n = glm::normalize(nm * n);
  if (glm::determinant(glm::mat3(m)) < 0.0f)
    for (auto& t : mesh.triangles) std::swap(t.y, t.z);
}

// What the loaded objects are made of: which node(s) each object is, for motions.
struct ObjectNodes {
  std::vector<SceneObject> objects;
  std::vector<std::vector<size_t>> nodes;  // per object: its node (plain) or nodes (instanced)
};

ObjectNodes build_objects(const GltfDocument& doc, const std::vector<GltfNode>& nodes,
                          const std::string& prefix, bool instanced) {
  const std::vector<glm::dmat4> world = world_matrices(nodes);
  std::map<int, std::vector<size_t>> users;  // mesh -> nodes, in node order
  std::vector<int> order;                    // meshes in order of first use
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].mesh < 0) continue;
    if (!instanced) {  // every node its own plain object (a copy of its mesh)
      order.push_back(static_cast<int>(i));
      users[static_cast<int>(i)] = {i};
      continue;
    }
    if (!users.count(nodes[i].mesh)) order.push_back(nodes[i].mesh);
    users[nodes[i].mesh].push_back(i);
  }
  std::set<std::string> node_names;
  for (const auto& n : nodes) node_names.insert(n.name);
  ObjectNodes out;
  std::map<int, TriangleMesh> meshes;  // read once each
  for (int key : order) {
    const std::vector<size_t>& us = users[key];
    const int m = nodes[us[0]].mesh;
    if (!meshes.count(m)) meshes[m] = read_mesh(doc, static_cast<size_t>(m));
    const TriangleMesh& local = meshes[m];
    SceneObject o;
    o.source = "glTF " + doc.file() + " meshes[" + std::to_string(m) + "]";
    if (us.size() == 1) {
      o.name = prefix + nodes[us[0]].name;
      o.mesh = local;
      place(to_float(world[us[0]]), o.mesh);
      validate_mesh(o.mesh, doc.file() + ": nodes[" + std::to_string(us[0]) + "] (placed)");
    } else {
      const nlohmann::json& mj = doc.array("meshes")[static_cast<size_t>(m)];
      std::string name = mj.contains("name") && mj["name"].is_string()
                             ? mj["name"].get<std::string>()
                             : "meshes[" + std::to_string(m) + "]";
      if (name.empty() || node_names.count(name)) name = "meshes[" + std::to_string(m) + "]";
      o.name = prefix + name;
      o.mesh = local;
      const Bounds b = local.bounds();
      for (size_t n : us) {
        o.instances.push_back(to_float(world[n]));
        o.instance_names.push_back(prefix + nodes[n].name);
        validate_instance(o.instances.back(), b,
                          doc.file() + ": nodes[" + std::to_string(n) + "] (placement)");
      }
    }
    out.objects.push_back(std::move(o));
    out.nodes.push_back(us);
  }
  return out;
}

CameraPose camera_pose(const glm::dmat4& w) {
  CameraPose p;
  const glm::dvec3 eye(w[3]);
  const glm::dvec3 forward = glm::normalize(glm::dmat3(w) * glm::dvec3(0.0, 0.0, -1.0));
  p.eye = glm::vec3(eye);
  p.target = glm::vec3(eye + forward);
  p.up = glm::vec3(glm::normalize(glm::dmat3(w) * glm::dvec3(0.0, 1.0, 0.0)));
  return p;
}

// Still views of every perspective camera node (at the rest pose).
std::vector<size_t> read_cameras(const GltfDocument& doc, const std::vector<GltfNode>& nodes,
                                 std::vector<View>& views) {
  const std::vector<glm::dmat4> world = world_matrices(nodes);
  std::vector<size_t> camera_nodes;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].camera < 0) continue;
    const std::string at = "cameras[" + std::to_string(nodes[i].camera) + "]";
    const nlohmann::json& c = doc.array("cameras")[static_cast<size_t>(nodes[i].camera)];
    const std::string type = c.is_object() ? c.value("type", "") : "";
    if (type == "orthographic")
      doc.fail(at, "orthographic camera (node '" + nodes[i].name +
                       "'): aoeval renders perspective views only");
    if (type != "perspective" || !c.contains("perspective") || !c["perspective"].is_object())
      doc.fail(at, "expected a perspective camera");
    const nlohmann::json& yfov = c["perspective"].value("yfov", nlohmann::json());
    const double deg = yfov.is_number() ? yfov.get<double>() * 180.0 / M_PI : 0.0;
    if (!(deg >= 1.0 && deg <= 170.0))
      doc.fail(at + ".perspective.yfov", "must be a number of radians giving 1 to 170 degrees");
    View v;
    v.name = nodes[i].name;
    v.fov_y_deg = static_cast<float>(deg);
    const glm::dmat3 linear(world[i]);
    if (!(std::abs(glm::determinant(linear)) > 1e-12))
      doc.fail("nodes[" + std::to_string(i) + "]", "camera node with a singular transform");
    const CameraPose p = camera_pose(world[i]);
    v.eye = p.eye;
    v.target = p.target;
    v.up = p.up;
    views.push_back(v);
    camera_nodes.push_back(i);
  }
  return camera_nodes;
}

// The sequence views of one animation: for each camera node, every frame's camera, and every
// moving object's placements' motion from the rest pose.
void add_sequences(const GltfDocument& doc, const std::vector<GltfNode>& nodes,
                   const GltfAnimation& anim, size_t a, const ObjectNodes& on,
                   const std::vector<size_t>& cameras, std::vector<View>& views) {
  const double span = (anim.end - anim.start) * kGltfFps;
  if (span + 1.0 > kMaxSequenceFrames)
    doc.fail("animations[" + std::to_string(a) + "]",
             "lasts more than " + std::to_string(kMaxSequenceFrames) + " frames at 30 fps");
  const int frames = static_cast<int>(std::floor(span + 1e-6)) + 1;
  const std::vector<glm::dmat4> rest = world_matrices(nodes);
  Sequence s;
  s.frames = frames;
  s.fps = kGltfFps;
  std::vector<std::vector<CameraPose>> poses(cameras.size());
  std::vector<std::vector<std::vector<glm::mat4>>> motion(on.objects.size());
  std::vector<bool> moves(on.objects.size(), false);
  for (int k = 0; k < frames; ++k) {
    const double t = anim.start + k / kGltfFps;
    const std::vector<glm::dmat4> w = world_matrices(posed_nodes(nodes, &anim, t));
    for (size_t c = 0; c < cameras.size(); ++c) poses[c].push_back(camera_pose(w[cameras[c]]));
    for (size_t o = 0; o < on.objects.size(); ++o) {
      std::vector<glm::mat4> m;
      for (size_t n : on.nodes[o]) {
        // Unmoved nodes keep an exact identity (the same doubles): still frames stay still.
        m.push_back(w[n] == rest[n] ? glm::mat4(1.0f) : to_float(w[n] * glm::inverse(rest[n])));
        if (m.back() != glm::mat4(1.0f)) moves[o] = true;
      }
      motion[o].push_back(std::move(m));
    }
  }
  for (size_t o = 0; o < on.objects.size(); ++o)
    if (moves[o]) s.sampled_motion[on.objects[o].name] = std::move(motion[o]);
  for (size_t c = 0; c < cameras.size(); ++c) {
    View v = views[c];  // the still view of that camera: name, fov
    v.name = nodes[cameras[c]].name + "@" + anim.name;
    v.eye = poses[c][0].eye;
    v.target = poses[c][0].target;
    v.up = poses[c][0].up;
    Sequence sc = s;
    sc.sampled_camera = std::move(poses[c]);
    v.sequence = std::move(sc);
    views.push_back(std::move(v));
  }
}

// Refuses a camera whose eye is inside geometry: the six axis rays from the eye all hit, and at
// least five of them a back face (the eye is enclosed by surfaces facing away from it; one ray may
// meet a coplanar front face first, as a box resting on a floor shows its bottom).
void check_camera_outside(const GltfDocument& doc, const Scene& scene,
                          const std::vector<size_t>& cameras, const std::vector<GltfNode>& nodes) {
  if (cameras.empty() || scene.objects.empty()) return;
  const Scene copies = has_instances(scene) ? scene_as_copies(scene) : scene;
  const EmbreeScene embree(copies, BuildQuality::low);
  for (size_t c = 0; c < cameras.size(); ++c) {
    const glm::vec3 eye = scene.views[c].eye;
    int back_hits = 0, hits = 0;
    for (int d = 0; d < 6; ++d) {
      glm::vec3 dir(0.0f);
      dir[d / 2] = d % 2 ? -1.0f : 1.0f;
      RTCRayHit rh{};
      rh.ray.org_x = eye.x;
      rh.ray.org_y = eye.y;
      rh.ray.org_z = eye.z;
      rh.ray.dir_x = dir.x;
      rh.ray.dir_y = dir.y;
      rh.ray.dir_z = dir.z;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = 1e30f;
      rh.ray.mask = 0xFFFFFFFFu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect1(embree.handle(), &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      ++hits;
      const TriangleMesh& mesh = copies.objects[hit_placement(rh.hit)].mesh;
      const glm::uvec3 t = mesh.triangles[rh.hit.primID];
      const glm::vec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                     mesh.positions[t.z] - mesh.positions[t.x]);
      if (glm::dot(n, dir) > 0.0f) ++back_hits;
    }
    if (back_hits >= 5 && hits == 6)
      doc.fail("nodes[" + std::to_string(cameras[c]) + "]",
               "camera '" + nodes[cameras[c]].name +
                   "' is inside geometry (its axis rays hit back faces)");
  }
}

}  // namespace

std::vector<SceneObject> load_gltf_objects(const std::string& path, const std::string& prefix,
                                           bool instanced) {
  const GltfDocument doc(path);
  const std::vector<GltfNode> nodes = read_gltf_nodes(doc);
  return build_objects(doc, nodes, prefix, instanced).objects;
}

Scene load_gltf_scene(const std::string& path) {
  const GltfDocument doc(path);
  const std::vector<GltfNode> nodes = read_gltf_nodes(doc);
  const std::vector<GltfAnimation> animations = read_gltf_animations(doc, nodes);
  ObjectNodes on = build_objects(doc, nodes, "", true);
  Scene scene;
  scene.file = path;
  scene.name = fs::path(path).stem().string();
  const std::vector<size_t> cameras = read_cameras(doc, nodes, scene.views);
  if (cameras.empty()) doc.fail("nodes", "no camera node: a glTF scene needs a perspective camera");
  if (on.objects.empty()) doc.fail("nodes", "no mesh node: nothing to render");
  scene.objects = on.objects;
  check_camera_outside(doc, scene, cameras, nodes);
  for (size_t a = 0; a < animations.size(); ++a)
    add_sequences(doc, nodes, animations[a], a, on, cameras, scene.views);
  return scene;
}

}  // namespace aoeval
