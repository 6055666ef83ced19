#include "scenes/sequence.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "base/errors.h"
#include "base/json_reader.h"

namespace aoeval {

const char* jitter_name(Jitter j) {
  return j == Jitter::halton ? "halton" : "none";
}

namespace {

int read_frame(JsonReader& r, int frames) {
  return static_cast<int>(r.integer("frame", 0, frames - 1));
}

// Keys must be strictly increasing in frame: a repeated or backwards frame is almost always a
// copy-paste slip, and linear interpolation between them is undefined.
template <typename Key>
void check_order(const std::vector<Key>& keys, JsonReader& parent, const std::string& field) {
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].frame <= keys[i - 1].frame)
      parent.fail(field + "[" + std::to_string(i) + "].frame",
                  "keys must be in increasing frame order (frame " + std::to_string(keys[i].frame) +
                      " follows frame " + std::to_string(keys[i - 1].frame) + ")");
}

double halton(int index, int base) {
  double f = 1.0, r = 0.0;
  for (int i = index; i > 0; i /= base) {
    f /= base;
    r += f * (i % base);
  }
  return r;
}

// Linear interpolation over keys sorted by frame; the nearest key holds outside them.
template <typename Key, typename Lerp>
Key interpolate(const std::vector<Key>& keys, int frame, Lerp lerp) {
  if (frame <= keys.front().frame) return keys.front();
  if (frame >= keys.back().frame) return keys.back();
  size_t i = 1;
  while (keys[i].frame < frame) ++i;
  const Key& a = keys[i - 1];
  const Key& b = keys[i];
  const float t = static_cast<float>(frame - a.frame) / static_cast<float>(b.frame - a.frame);
  Key k = lerp(a, b, t);
  k.frame = frame;
  return k;
}

}  // namespace

Sequence read_sequence(JsonReader r, glm::vec3 eye, glm::vec3 target) {
  Sequence s;
  s.frames = static_cast<int>(r.integer("frames", 1, kMaxSequenceFrames));
  s.fps = r.number("fps", 30.0, 1e-3, 1e6);
  s.jitter =
      r.choice("jitter", "none", {"none", "halton"}) == "halton" ? Jitter::halton : Jitter::none;
  if (r.has("camera")) {
    for (auto& k : r.array_of_objects("camera", 1)) {
      CameraKey key;
      key.frame = read_frame(k, s.frames);
      key.eye = k.vec3("eye");
      key.target = k.vec3("target");
      k.finish();
      if (!(glm::length(glm::dvec3(key.target) - glm::dvec3(key.eye)) > 1e-6))
        k.fail("target", "eye and target coincide");
      if (key.frame == 0 &&
          (glm::length(key.eye - eye) > 1e-6f || glm::length(key.target - target) > 1e-6f))
        k.fail("eye",
               "the key at frame 0 must equal the view's own eye and target (the view "
               "holds frame 0's camera)");
      s.camera.push_back(key);
    }
    check_order(s.camera, r, "camera");
    if (s.camera.front().frame != 0) s.camera.insert(s.camera.begin(), CameraKey{0, eye, target});
  }
  if (r.has("objects")) {
    const nlohmann::json& objects = r.raw("objects");
    if (!objects.is_object())
      r.fail("objects", "expected an object mapping object names to arrays of keys");
    for (const auto& [name, list] : objects.items()) {
      const std::string field = "objects." + name;
      if (!list.is_array() || list.empty()) r.fail(field, "expected a non-empty array of keys");
      std::vector<ObjectKey> keys;
      for (size_t i = 0; i < list.size(); ++i) {
        const std::string where = field + "[" + std::to_string(i) + "]";
        if (!list[i].is_object()) r.fail(where, "expected an object");
        JsonReader k(list[i], r.file(), r.where(where));
        ObjectKey key;
        key.frame = read_frame(k, s.frames);
        key.translate = k.vec3("translate", key.translate);
        key.rotate_deg = k.vec3("rotate_deg", key.rotate_deg);
        key.scale = k.vec3("scale", key.scale);
        for (int c = 0; c < 3; ++c)
          if (!(key.scale[c] > 0.0f)) k.fail("scale", "scale components must be positive");
        k.finish();
        keys.push_back(key);
      }
      check_order(keys, r, field);
      s.objects[name] = std::move(keys);
    }
  }
  r.finish();
  return s;
}

void check_sequence_objects(const Sequence& s, const std::vector<std::string>& object_names,
                            const std::string& file, const std::string& view) {
  for (const auto& [name, keys] : s.objects) {
    if (std::find(object_names.begin(), object_names.end(), name) != object_names.end()) continue;
    std::string known;
    for (const auto& n : object_names) known += (known.empty() ? "" : ", ") + n;
    throw InputError(file + ": views." + view + ".sequence.objects." + name +
                     ": the scene has no object named '" + name + "' (objects: " + known + ")");
  }
}

CameraKey camera_at(const Sequence& s, glm::vec3 eye, glm::vec3 target, int frame) {
  if (s.camera.empty()) return CameraKey{frame, eye, target};
  return interpolate(s.camera, frame, [](const CameraKey& a, const CameraKey& b, float t) {
    return CameraKey{0, a.eye + t * (b.eye - a.eye), a.target + t * (b.target - a.target)};
  });
}

ObjectKey object_key_at(const Sequence& s, const std::string& name, int frame) {
  const auto it = s.objects.find(name);
  if (it == s.objects.end()) return ObjectKey{frame};
  return interpolate(it->second, frame, [](const ObjectKey& a, const ObjectKey& b, float t) {
    return ObjectKey{0, a.translate + t * (b.translate - a.translate),
                     a.rotate_deg + t * (b.rotate_deg - a.rotate_deg),
                     a.scale + t * (b.scale - a.scale)};
  });
}

glm::mat4 motion_matrix(const ObjectKey& key, glm::vec3 pivot) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), key.translate + pivot);
  m = glm::rotate(m, glm::radians(key.rotate_deg.z), glm::vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(key.rotate_deg.y), glm::vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(key.rotate_deg.x), glm::vec3(1, 0, 0));
  m = glm::scale(m, key.scale);
  return glm::translate(m, -pivot);
}

glm::vec2 frame_jitter(const Sequence& s, int frame) {
  if (s.jitter == Jitter::none) return glm::vec2(0.0f);
  const int index = 1 + (frame % 16);
  return glm::vec2(static_cast<float>(halton(index, 2) - 0.5),
                   static_cast<float>(halton(index, 3) - 0.5));
}

}  // namespace aoeval
