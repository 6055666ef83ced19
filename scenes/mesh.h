// Triangle meshes: the one geometric currency of aoeval. Loaders, generators, the Embree scene and
// the object-space estimators all speak it.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace aoeval {

struct Bounds {
  glm::vec3 lower{1e30f};
  glm::vec3 upper{-1e30f};
  void extend(const glm::vec3& p);
  void extend(const Bounds& b);
  bool empty() const { return lower.x > upper.x; }
  glm::vec3 center() const { return 0.5f * (lower + upper); }
  glm::vec3 extent() const { return upper - lower; }
};

struct TriangleMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;  // indices into positions, counter-clockwise = front
  // Optional per-vertex shading normals (same size as positions); empty means "use the geometric
  // normal". Generators leave flat parts (leaves, walls) without them.
  std::vector<glm::vec3> normals;

  size_t triangle_count() const { return triangles.size(); }
  size_t vertex_count() const { return positions.size(); }
  Bounds bounds() const;

  // Appends another mesh, offsetting its indices. If exactly one side has normals, the other side
  // gets its geometric normals so the result stays consistent.
  void append(const TriangleMesh& other);
};

// Area-weighted smooth vertex normals (replaces `normals`).
void compute_vertex_normals(TriangleMesh& mesh);

// 64-bit FNV-1a over positions, triangles and normals, in that order, as raw little-endian bytes:
// equal hashes mean bit-identical meshes. Used for generator determinism and content-addressed
// caches.
uint64_t content_hash(const TriangleMesh& mesh);

// Checks finite coordinates, indices in range and non-empty geometry. Throws InputError naming
// `where` (e.g. "scenes/corpus/bunny.json: objects[0].mesh (bunny00.off)") on failure.
void validate_mesh(const TriangleMesh& mesh, const std::string& where);

std::string hash_hex(uint64_t hash);

}  // namespace aoeval
