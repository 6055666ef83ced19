// glTF 2.0 node transforms and animations (glTF spec §3.5 and Appendix C): nodes' local TRS (or
// matrix), their world matrices, and animation samplers evaluated at a time: STEP and LINEAR
// exactly, CUBICSPLINE as the spec's Hermite form, rotations as quaternions (slerp along the
// shorter arc, cubic results normalised), never Euler angles. Double precision throughout.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "scenes/gltf_document.h"

namespace aoeval {

struct GltfNode {
  std::string name;  // unique: the node's name, or "nodes[i]" (see read_gltf_nodes)
  int parent = -1;
  int mesh = -1, camera = -1;
  bool has_matrix = false;  // "matrix" given (then not animatable)
  glm::dmat4 matrix{1.0};
  glm::dvec3 translation{0.0}, scale{1.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // w, x, y, z
};

enum class GltfPath { translation, rotation, scale };
enum class GltfInterpolation { step, linear, cubic };

struct GltfChannel {
  size_t node = 0;
  GltfPath path = GltfPath::translation;
  GltfInterpolation interpolation = GltfInterpolation::linear;
  std::vector<double> times;   // strictly increasing
  std::vector<double> values;  // per key: n components (3 n for cubic: in-tangent, value, out)
};

struct GltfAnimation {
  std::string name;  // the animation's name, or "animations[i]"
  std::vector<GltfChannel> channels;
  double start = 0.0, end = 0.0;  // the range of every sampler's input
};

// The nodes with their parents; names made unique ("<name>", then "<name>.<i>" for a repeat;
// "nodes[i]" when unnamed). Errors: bad indices, a node with two parents or in a cycle, a matrix
// or TRS that is not finite.
std::vector<GltfNode> read_gltf_nodes(const GltfDocument& doc);
// Every animation; errors name "animations[a].channels[c]" or ".samplers[s]": no keys, times not
// increasing, a channel on a node with a matrix, "weights" (morph targets) channels.
std::vector<GltfAnimation> read_gltf_animations(const GltfDocument& doc,
                                                const std::vector<GltfNode>& nodes);

// The channel's value at time t (n = 3 or 4 components; quaternions as x, y, z, w).
std::vector<double> sample_channel(const GltfChannel& c, double t);

// Nodes' local TRS with `animation`'s channels applied at time t (nullptr: the rest pose).
std::vector<GltfNode> posed_nodes(const std::vector<GltfNode>& nodes,
                                  const GltfAnimation* animation, double t);
// World matrices of every node (parent * local), in node order.
std::vector<glm::dmat4> world_matrices(const std::vector<GltfNode>& nodes);

}  // namespace aoeval
