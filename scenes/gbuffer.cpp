#include "scenes/gbuffer.h"

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <glm/matrix.hpp>
#include <limits>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/input_limits.h"
#include "base/version.h"
#include "scenes/instances.h"

namespace aoeval {

Camera make_camera(const View& view, int width, int height) {
  Camera c;
  c.eye = view.eye;
  c.forward = glm::normalize(view.target - view.eye);
  c.right = glm::normalize(glm::cross(c.forward, view.up));
  c.up = glm::cross(c.right, c.forward);
  c.tan_half_fov_y = std::tan(0.5f * glm::radians(view.fov_y_deg));
  c.width = width > 0 ? width : view.width;
  c.height = height > 0 ? height : view.height;
  // Views read from scene files are checked in read_view; this catches any other source (a
  // G-buffer header, a generated view) before a NaN ray reaches Embree, which asserts on it.
  const bool finite =
      std::isfinite(c.tan_half_fov_y) && std::isfinite(c.eye.x + c.eye.y + c.eye.z) &&
      std::isfinite(c.forward.x + c.forward.y + c.forward.z) &&
      std::isfinite(c.right.x + c.right.y + c.right.z) && std::isfinite(c.up.x + c.up.y + c.up.z);
  if (!finite)
    throw InputError("view '" + view.name +
                     "': the camera (eye, target, up, fov_y_deg) gives a "
                     "non-finite viewing basis");
  return c;
}

namespace {

struct PlacedObject {
  const glm::mat4* matrix = nullptr;
  glm::mat3 normal_matrix{1.0f};
  bool mirrored = false;  // negative determinant: the copies swap the winding
};

// Where the ray org + t dir crosses the plane of (p0, p1, p2), as barycentrics (u, v) of p1 and p2;
// left unchanged when the ray is parallel to the plane to double precision.
void world_barycentrics(const glm::vec3& org, const glm::vec3& dir, const glm::vec3& p0,
                        const glm::vec3& p1, const glm::vec3& p2, float& u, float& v) {
  const glm::dvec3 d(dir), e1 = glm::dvec3(p1) - glm::dvec3(p0),
                           e2 = glm::dvec3(p2) - glm::dvec3(p0);
  const glm::dvec3 pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (!(std::fabs(det) > 1e-300)) return;
  const glm::dvec3 tv = glm::dvec3(org) - glm::dvec3(p0);
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double uu = glm::dot(tv, pv) / det, vv = glm::dot(d, qv) / det;
  if (!std::isfinite(uu) || !std::isfinite(vv)) return;
  u = static_cast<float>(uu);
  v = static_cast<float>(vv);
}

glm::vec3 world_point(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, float u,
                      float v) {
  const double uu = u, vv = v, ww = 1.0 - uu - vv;
  return glm::vec3(ww * glm::dvec3(p0) + uu * glm::dvec3(p1) + vv * glm::dvec3(p2));
}

}  // namespace

GBuffer render_gbuffer(const EmbreeScene& es, const Camera& camera) {
  GBuffer g;
  g.width = camera.width;
  g.height = camera.height;
  g.camera = camera;
  check_memory_for_resolution(g.width, g.height);
  const size_t n = g.pixel_count();
  g.coverage.assign(n, 0.0f);
  g.depth.assign(n, 0.0f);
  g.position.assign(n, glm::vec3(0.0f));
  g.normal.assign(n, glm::vec3(0.0f));
  g.geometric_normal.assign(n, glm::vec3(0.0f));
  g.object_id.assign(n, -1.0f);
  const Scene& scene = es.scene();
  const PlacementIds ids(scene);
  std::vector<PlacedObject> placements(ids.count);  // by id; matrix null for a plain object
  for (size_t i = 0; i < scene.objects.size(); ++i)
    for (size_t k = 0; k < scene.objects[i].instances.size(); ++k) {
      const glm::mat4& m = scene.objects[i].instances[k];
      placements[ids.first[i] + k] = {&m, placement_normal_matrix(m),
                                      glm::determinant(glm::mat3(m)) < 0.0f};
    }

  parallel_for_embree(tbb::blocked_range2d<int>(0, g.height, 8, 0, g.width, 8), [&](const auto& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int j = r.rows().begin(); j < r.rows().end(); ++j) {
      for (int i = r.cols().begin(); i < r.cols().end(); ++i) {
        const glm::vec3 dir = camera.direction(i, j);
        RTCRayHit rh{};
        rh.ray.org_x = camera.eye.x;
        rh.ray.org_y = camera.eye.y;
        rh.ray.org_z = camera.eye.z;
        rh.ray.dir_x = dir.x;
        rh.ray.dir_y = dir.y;
        rh.ray.dir_z = dir.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(es.handle(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;

        const unsigned id = hit_placement(rh.hit);
        const size_t object = ids.object_of(id);
        const SceneObject& o = scene.objects[object];
        const TriangleMesh& mesh = o.mesh;
        glm::uvec3 tri = mesh.triangles[rh.hit.primID];
        glm::vec3 p0 = mesh.positions[tri.x], p1 = mesh.positions[tri.y],
                  p2 = mesh.positions[tri.z];
        const PlacedObject* placed = nullptr;
        if (!o.instances.empty()) {
          // The world-space triangle, by the same float operations as the object's copies
          // (instances.h scene_as_copies), winding included.
          placed = &placements[id];
          if (placed->mirrored) {
            std::swap(tri.y, tri.z);
            std::swap(p1, p2);
          }
          p0 = place_point(*placed->matrix, p0);
          p1 = place_point(*placed->matrix, p1);
          p2 = place_point(*placed->matrix, p2);
        }
        // Barycentrics recomputed in world space, in double (Moller-Trumbore 1997): Embree's u, v
        // of an instance hit come from the ray in the prototype's space and differ in the last bits
        // from a copy's, so both take these; P then lies on the triangle's plane to float
        // precision.
        float u = rh.hit.u, v = rh.hit.v;
        world_barycentrics(camera.eye, dir, p0, p1, p2, u, v);
        const float w = 1.0f - u - v;
        const glm::vec3 p = world_point(p0, p1, p2, u, v);
        glm::vec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        glm::vec3 ns = ng;
        if (!mesh.normals.empty()) {
          glm::vec3 n0 = mesh.normals[tri.x], n1 = mesh.normals[tri.y], n2 = mesh.normals[tri.z];
          if (placed) {
            n0 = glm::normalize(placed->normal_matrix * n0);
            n1 = glm::normalize(placed->normal_matrix * n1);
            n2 = glm::normalize(placed->normal_matrix * n2);
          }
          glm::vec3 s = w * n0 + u * n1 + v * n2;
          float len = glm::length(s);
          if (len > 1e-12f && std::isfinite(len)) ns = s / len;
        }
        if (glm::dot(ng, dir) > 0.0f) {  // two-sided: face the viewer
          ng = -ng;
          ns = -ns;
        }
        const size_t k = g.index(i, j);
        g.coverage[k] = 1.0f;
        g.depth[k] = glm::dot(p - camera.eye, camera.forward);
        g.position[k] = p;
        g.normal[k] = ns;
        g.geometric_normal[k] = ng;
        g.object_id[k] = static_cast<float>(id);
      }
    }
  });
  return g;
}

const std::vector<std::string>& gbuffer_channel_names() {
  static const std::vector<std::string> names = {"A",   "Z",   "P.X",  "P.Y",  "P.Z",  "N.X",
                                                 "N.Y", "N.Z", "Ng.X", "Ng.Y", "Ng.Z", "objectId"};
  return names;
}

OIIO::ImageBuf gbuffer_to_image(const GBuffer& g) {
  std::vector<std::string> names = gbuffer_channel_names();
  const bool motion = !g.motion.empty();
  if (motion) names.insert(names.end(), {"motion.X", "motion.Y", "disoccluded"});
  OIIO::ImageSpec spec(g.width, g.height, static_cast<int>(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  const size_t nc = names.size();
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    float* o = px + k * nc;
    o[0] = g.coverage[k];
    o[1] = g.depth[k];
    for (int c = 0; c < 3; ++c) {
      o[2 + c] = g.position[k][c];
      o[5 + c] = g.normal[k][c];
      o[8 + c] = g.geometric_normal[k][c];
    }
    o[11] = g.object_id[k];
    if (motion) {
      o[12] = g.motion[k].x;
      o[13] = g.motion[k].y;
      o[14] = g.disoccluded[k];
    }
  }
  return image;
}

std::string camera_to_json(const Camera& c) {
  auto v = [](const glm::vec3& x) { return nlohmann::json::array({x.x, x.y, x.z}); };
  nlohmann::json j = {{"eye", v(c.eye)},
                      {"forward", v(c.forward)},
                      {"right", v(c.right)},
                      {"up", v(c.up)},
                      {"fov_y_deg", glm::degrees(2.0f * std::atan(c.tan_half_fov_y))},
                      {"width", c.width},
                      {"height", c.height}};
  // Only a jittered sequence frame carries it, so the cache keys of every still view (which
  // hash this text) are unchanged.
  if (c.jitter != glm::vec2(0.0f)) j["jitter"] = nlohmann::json::array({c.jitter.x, c.jitter.y});
  return j.dump();
}

Attributes gbuffer_attributes(const Scene& scene, const View& view, const Camera& camera) {
  return gbuffer_attributes(scene, scene.content_hash(), view, camera);
}

Attributes gbuffer_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                              const Camera& camera) {
  return {{"aoeval:scene", scene.name},
          {"aoeval:view", view.name},
          {"aoeval:scene_hash", hash_hex(scene_hash)},
          {"aoeval:camera", camera_to_json(camera)},
          {"aoeval:version", kAoevalVersion}};
}

GBuffer read_gbuffer(const std::string& path) {
  OIIO::ImageBuf image = read_image(path);
  GBuffer g;
  g.width = image.spec().width;
  g.height = image.spec().height;
  std::vector<int> idx;
  for (const auto& name : gbuffer_channel_names()) idx.push_back(channel_index(image, name, path));
  const std::string cam = string_attribute(image, "aoeval:camera");
  if (cam.empty()) throw InputError(path + ": header attribute 'aoeval:camera' is missing");
  try {
    auto j = nlohmann::json::parse(cam);
    auto v = [&](const char* k) { return glm::vec3(j[k][0], j[k][1], j[k][2]); };
    g.camera.eye = v("eye");
    g.camera.forward = v("forward");
    g.camera.right = v("right");
    g.camera.up = v("up");
    g.camera.tan_half_fov_y = std::tan(0.5f * glm::radians(j["fov_y_deg"].get<float>()));
    g.camera.width = g.width;
    g.camera.height = g.height;
    if (j.contains("jitter")) g.camera.jitter = glm::vec2(j["jitter"][0], j["jitter"][1]);
  } catch (const nlohmann::json::exception&) {
    throw InputError(path + ": header attribute 'aoeval:camera' is not valid camera JSON");
  }
  const size_t n = g.pixel_count();
  g.coverage.resize(n);
  g.depth.resize(n);
  g.position.resize(n);
  g.normal.resize(n);
  g.geometric_normal.resize(n);
  g.object_id.resize(n);
  const auto* px = static_cast<const float*>(image.localpixels());
  const int nc = image.spec().nchannels;
  for (size_t k = 0; k < n; ++k) {
    const float* s = px + k * nc;
    g.coverage[k] = s[idx[0]];
    g.depth[k] = s[idx[1]];
    g.position[k] = {s[idx[2]], s[idx[3]], s[idx[4]]};
    g.normal[k] = {s[idx[5]], s[idx[6]], s[idx[7]]};
    g.geometric_normal[k] = {s[idx[8]], s[idx[9]], s[idx[10]]};
    g.object_id[k] = s[idx[11]];
  }
  const int mx = image.spec().channelindex("motion.X"), my = image.spec().channelindex("motion.Y"),
            dis = image.spec().channelindex("disoccluded");
  if (mx >= 0 && my >= 0 && dis >= 0) {
    g.motion.resize(n);
    g.disoccluded.resize(n);
    for (size_t k = 0; k < n; ++k) {
      const float* s = px + k * nc;
      g.motion[k] = {s[mx], s[my]};
      g.disoccluded[k] = s[dis];
    }
  }
  check_gbuffer_values(g, path);
  return g;
}

void check_gbuffer_values(const GBuffer& g, const std::string& path) {
  if (g.motion.empty() && g.disoccluded.empty()) return;
  const size_t n = g.pixel_count();
  if (g.motion.size() != n || g.disoccluded.size() != n)
    throw InputError(path + ": motion.X/Y and disoccluded hold " + std::to_string(g.motion.size()) +
                     " and " + std::to_string(g.disoccluded.size()) + " values for " +
                     std::to_string(n) + " pixels");
  auto value_text = [](float v) { return std::isnan(v) ? "NaN" : v > 0 ? "inf" : "-inf"; };
  for (size_t k = 0; k < n; ++k) {
    if (!g.covered(k)) continue;
    const std::pair<const char*, float> values[] = {{"motion.X", g.motion[k].x},
                                                    {"motion.Y", g.motion[k].y},
                                                    {"disoccluded", g.disoccluded[k]}};
    for (const auto& [channel, v] : values)
      if (!std::isfinite(v))
        throw InputError(path + ": " + channel + " is " + value_text(v) + " at covered pixel (" +
                         std::to_string(k % g.width) + ", " + std::to_string(k / g.width) +
                         ") (a sequence G-buffer's motion is a finite offset in pixels)");
  }
}

}  // namespace aoeval
