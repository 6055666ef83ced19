// Sequences (CONTRACT §10): a view whose camera and objects move over frames. Keyframes are
// interpolated linearly (eye, target; translate, rotate_deg, scale), which is enough for the
// corpus's orbits and walks and keeps every frame's pose exact and cheap to recompute. Before a
// channel's first key and after its last, the nearest key holds.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace aoeval {

class JsonReader;

struct CameraKey {
  int frame = 0;
  glm::vec3 eye{0.0f}, target{0.0f};
};

// A world-space motion applied on top of the object's placement (its "transform" and "fit"):
// scale, then rotate (X, then Y, then Z, degrees), both about the centre of the placed object's
// bounding box, then translate. Keys may leave out a channel: it is then the identity
// (translate 0, rotate_deg 0, scale 1) at that key.
struct ObjectKey {
  int frame = 0;
  glm::vec3 translate{0.0f}, rotate_deg{0.0f}, scale{1.0f};
};

enum class Jitter { none, halton };

// A camera as sampled at one frame (glTF animations, scenes/gltf_scene.h).
struct CameraPose {
  glm::vec3 eye{0.0f}, target{0.0f}, up{0.0f, 1.0f, 0.0f};
};

struct Sequence {
  int frames = 1;
  double fps = 30.0;
  Jitter jitter = Jitter::none;
  std::vector<CameraKey> camera;                          // by frame; may be empty (static)
  std::map<std::string, std::vector<ObjectKey>> objects;  // object name -> keys by frame
  // glTF animations (scenes/gltf_scene.h) are sampled ahead, not keyed. When non-empty,
  // `sampled_camera` holds every frame's camera (up included), and `sampled_motion` the world-space
  // motion of each named object's placements, [frame][placement] (one placement for a plain
  // object, one per instance otherwise); they take the place of `camera` and `objects`.
  std::vector<CameraPose> sampled_camera;
  std::map<std::string, std::vector<std::vector<glm::mat4>>> sampled_motion;
};

// The largest sequence a view may ask for (a typo guard like the sweep's point limit): 100,000
// frames is an hour at 30 fps.
inline constexpr int kMaxSequenceFrames = 100000;

// Reads a view's "sequence" (`reader` is consumed). `eye` and `target` are the view's own: they are
// frame 0's camera, so a camera key at frame 0 must agree with them. Errors name the file and the
// field: unknown keys, frames outside [0, frames - 1], keys out of order.
Sequence read_sequence(JsonReader reader, glm::vec3 eye, glm::vec3 target);

// Fails (InputError naming `file` and the view) when the sequence names an object the scene lacks.
void check_sequence_objects(const Sequence& s, const std::vector<std::string>& object_names,
                            const std::string& file, const std::string& view);

// The camera of frame k: eye and target, linear between keys (the view's own at frame 0 when no
// key is at frame 0).
CameraKey camera_at(const Sequence& s, glm::vec3 eye, glm::vec3 target, int frame);
// Object `name`'s motion at frame k (identity for objects without keys).
ObjectKey object_key_at(const Sequence& s, const std::string& name, int frame);
// The world-space matrix of that motion for an object whose placed bounds have centre `pivot`.
glm::mat4 motion_matrix(const ObjectKey& key, glm::vec3 pivot);

// The sub-pixel offset of frame k's samples, in pixels, in (-0.5, 0.5)^2: zero without jitter;
// with "halton", the Halton (2, 3) point of index 1 + (k mod 16), minus 0.5 (the 16-frame cycle of
// TAA implementations, e.g. Karis 2014, "High-quality temporal supersampling").
glm::vec2 frame_jitter(const Sequence& s, int frame);

const char* jitter_name(Jitter j);

}  // namespace aoeval
