// glTF 2.0 scenes (README "glTF scenes"): a .glb/.gltf file as a scene, or as the objects of one
// entry of a scene file. Mesh nodes become objects named after the node (glTF's rest pose, world
// space); a mesh used by several nodes is one instanced object (one Embree geometry, one placement
// per node, named after the mesh). Every perspective camera node is a still view named after the
// node; every animation a sequence view "<camera>@<animation>" per camera node, sampled at 30 fps
// from the animation's first key time: frame k at t0 + k / 30 (scenes/gltf_animation.h).
#pragma once

#include <string>
#include <vector>

#include "scenes/scene.h"

namespace aoeval {

inline constexpr double kGltfFps = 30.0;

// The whole file as a scene: objects, views, sequences. InputError "file: glTF path: reason".
Scene load_gltf_scene(const std::string& path);

// The mesh nodes alone, at the rest pose, named "<prefix><node>" (a scene file's
// {"name": N, "gltf": ...} object passes "N/"). `instanced` false writes a mesh used by several
// nodes as one plain object per node (for the consumers that refuse instances).
std::vector<SceneObject> load_gltf_objects(const std::string& path, const std::string& prefix,
                                           bool instanced = true);

// Whether `path` names a glTF file (.glb or .gltf, any case).
bool is_gltf_path(const std::string& path);

}  // namespace aoeval
