#include "scenes/sequence_frame.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "base/errors.h"
#include "scenes/instances.h"

namespace aoeval {

SequenceFrame sequence_frame(const Scene& scene, const View& view, int k) {
  if (k < 0 || k >= view.frame_count())
    throw InputError("view '" + view.name + "': frame " + std::to_string(k) +
                     " is outside its frames 0.." + std::to_string(view.frame_count() - 1) +
                     (view.sequence ? "" : " (the view has no sequence)"));
  SequenceFrame f;
  f.index = k;
  f.view = view;
  const PlacementIds ids(scene);
  f.motion.assign(ids.count, glm::mat4(1.0f));
  if (!view.sequence) return f;
  const Sequence& s = *view.sequence;
  if (s.sampled_camera.empty()) {
    const CameraKey c = camera_at(s, view.eye, view.target, k);
    f.view.eye = c.eye;
    f.view.target = c.target;
  } else {
    const CameraPose& c = s.sampled_camera[static_cast<size_t>(k)];
    f.view.eye = c.eye;
    f.view.target = c.target;
    f.view.up = c.up;
  }
  f.jitter = frame_jitter(s, k);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    if (const auto sampled = s.sampled_motion.find(o.name); sampled != s.sampled_motion.end()) {
      const std::vector<glm::mat4>& m = sampled->second[static_cast<size_t>(k)];
      for (size_t j = 0; j < m.size(); ++j) {
        f.motion[ids.first[i] + j] = m[j];
        if (m[j] != glm::mat4(1.0f)) f.moves_objects = true;
      }
      continue;
    }
    if (!s.objects.count(o.name)) continue;
    // The pivot: the centre of the object as placed (all its instances).
    const glm::mat4 m = motion_matrix(object_key_at(s, o.name, k), placed_bounds(o).center());
    const size_t placements = std::max<size_t>(1, o.instances.size());
    for (size_t j = 0; j < placements; ++j) f.motion[ids.first[i] + j] = m;
    if (m != glm::mat4(1.0f)) f.moves_objects = true;
  }
  return f;
}

bool same_pose(const SequenceFrame& a, const SequenceFrame& b) {
  return a.view.eye == b.view.eye && a.view.target == b.view.target && a.view.up == b.view.up &&
         a.jitter == b.jitter && a.motion == b.motion;
}

int unchanged_since(const Scene& scene, const View& view, int k) {
  const SequenceFrame last = sequence_frame(scene, view, k);
  int j = k;
  while (j > 0 && same_pose(sequence_frame(scene, view, j - 1), last)) --j;
  return j;
}

Camera frame_camera(const SequenceFrame& frame, int width, int height) {
  Camera c = make_camera(frame.view, width, height);
  c.jitter = frame.jitter;
  return c;
}

Scene posed_scene(const Scene& base, const SequenceFrame& frame) {
  Scene s = base;
  const PlacementIds ids(s);
  for (size_t i = 0; i < s.objects.size(); ++i) {
    SceneObject& o = s.objects[i];
    if (!o.instances.empty()) {  // the prototype stays; every placement moves with its own motion
      for (size_t j = 0; j < o.instances.size(); ++j)
        o.instances[j] = frame.motion[ids.first[i] + j] * o.instances[j];
      continue;
    }
    const glm::mat4& m = frame.motion[ids.first[i]];
    if (m == glm::mat4(1.0f)) continue;
    const glm::mat3 linear(m);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    for (auto& v : o.mesh.positions) v = glm::vec3(m * glm::vec4(v, 1.0f));
    for (auto& n : o.mesh.normals) n = glm::normalize(normal_matrix * n);
    // Keyed scales are positive (read_sequence); a glTF pose may mirror: keep the winding.
    if (glm::determinant(linear) < 0.0f)
      for (auto& t : o.mesh.triangles) std::swap(t.y, t.z);
    if (o.proxy)
      for (auto& e : o.proxy->shapes) {
        e.center = glm::vec3(m * glm::vec4(e.center, 1.0f));
        for (int a = 0; a < 3; ++a) {
          const glm::vec3 axis = linear * (e.axes[a] * e.radii[a]);
          e.radii[a] = glm::length(axis);
          e.axes[a] = axis / e.radii[a];
        }
      }
  }
  return s;
}

bool project_to_pixel(const Camera& c, const glm::dvec3& p, glm::dvec2& pixel, double& depth) {
  const glm::dvec3 v = p - glm::dvec3(c.eye);
  depth = glm::dot(v, glm::dvec3(c.forward));
  if (!(depth > 0.0)) return false;
  const double t = c.tan_half_fov_y;
  const double aspect = static_cast<double>(c.width) / c.height;
  const double x = glm::dot(v, glm::dvec3(c.right)) / (depth * t * aspect);
  const double y = glm::dot(v, glm::dvec3(c.up)) / (depth * t);
  pixel = {0.5 * (x + 1.0) * c.width, 0.5 * (1.0 - y) * c.height};
  return true;
}

namespace {

// Whether P (world position at frame k - 1, projected at `q` with depth `z`) is hidden or on
// another object in frame k - 1's G-buffer (see add_motion).
bool disoccluded_in(const GBuffer& prev, const glm::dvec3& p, const glm::dvec2& q, double z,
                    float object) {
  if (!(q.x >= 0.0 && q.y >= 0.0 && q.x < prev.width && q.y < prev.height)) return true;
  // Frame k - 1's pixel (a, b) sampled (a + 0.5 + jitter.x, b + 0.5 + jitter.y).
  const int a =
      std::clamp(static_cast<int>(std::floor(q.x - prev.camera.jitter.x)), 0, prev.width - 1);
  const int b =
      std::clamp(static_cast<int>(std::floor(q.y - prev.camera.jitter.y)), 0, prev.height - 1);
  const size_t t = prev.index(a, b);
  if (!prev.covered(t) || prev.object_id[t] != object) return true;
  const double footprint = 2.0 * z * prev.camera.tan_half_fov_y / prev.height;
  const double distance =
      std::abs(glm::dot(p - glm::dvec3(prev.position[t]), glm::dvec3(prev.geometric_normal[t])));
  return distance > footprint;
}

}  // namespace

void add_motion(GBuffer& cur, const GBuffer* prev, const std::vector<glm::mat4>& motion_cur,
                const std::vector<glm::mat4>& motion_prev) {
  const size_t n = cur.pixel_count();
  cur.motion.assign(n, glm::vec2(0.0f));
  cur.disoccluded.assign(n, 0.0f);
  if (!prev) return;
  // Per object: from its pose at frame k to its pose at frame k - 1.
  std::vector<glm::dmat4> back(motion_cur.size());
  for (size_t o = 0; o < back.size(); ++o)
    back[o] = glm::dmat4(motion_prev[o]) * glm::inverse(glm::dmat4(motion_cur[o]));
  Camera unjittered = cur.camera;
  unjittered.jitter = glm::vec2(0.0f);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const auto& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      if (!cur.covered(k)) continue;
      const glm::dvec3 p(cur.position[k]);
      const auto object = static_cast<size_t>(cur.object_id[k]);
      const glm::dvec3 p_prev =
          object < back.size() ? glm::dvec3(back[object] * glm::dvec4(p, 1.0)) : p;
      glm::dvec2 now, then;
      double z_now = 0.0, z_then = 0.0;
      project_to_pixel(unjittered, p, now, z_now);
      if (!project_to_pixel(prev->camera, p_prev, then, z_then)) {
        cur.disoccluded[k] = 1.0f;
        continue;
      }
      cur.motion[k] = glm::vec2(now - then);
      if (disoccluded_in(*prev, p_prev, then, z_then, cur.object_id[k])) cur.disoccluded[k] = 1.0f;
    }
  });
}

GBuffer render_frame_gbuffer(const Scene& base, const View& view, int k, int width, int height) {
  const SequenceFrame now = sequence_frame(base, view, k);
  auto render = [&](const SequenceFrame& f) {
    const Scene posed = posed_scene(base, f);
    const EmbreeScene embree(posed);
    return render_gbuffer(embree, frame_camera(f, width, height));
  };
  GBuffer g = render(now);
  if (!view.sequence) return g;  // a still view's G-buffer, as `aoeval gbuffer` always wrote it
  if (k == 0) {
    add_motion(g, nullptr, now.motion, now.motion);
  } else {
    const SequenceFrame before = sequence_frame(base, view, k - 1);
    const GBuffer prev = render(before);
    add_motion(g, &prev, now.motion, before.motion);
  }
  return g;
}

Attributes frame_attributes(const Scene& posed, const View& view, const Camera& camera, int k) {
  Attributes a = gbuffer_attributes(posed, view, camera);
  if (view.sequence) a.emplace_back("aoeval:frame", std::to_string(k));
  return a;
}

}  // namespace aoeval
