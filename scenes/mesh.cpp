#include "scenes/mesh.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/geometric.hpp>

#include "base/errors.h"
#include "base/hash.h"
#include "base/input_limits.h"

namespace aoeval {

void Bounds::extend(const glm::vec3& p) {
  lower = glm::min(lower, p);
  upper = glm::max(upper, p);
}

void Bounds::extend(const Bounds& b) {
  if (b.empty()) return;
  extend(b.lower);
  extend(b.upper);
}

Bounds TriangleMesh::bounds() const {
  Bounds b;
  for (const auto& p : positions) b.extend(p);
  return b;
}

namespace {
glm::vec3 face_normal(const TriangleMesh& m, const glm::uvec3& t) {
  return glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
}
}  // namespace

void TriangleMesh::append(const TriangleMesh& other) {
  const bool theirs = !other.normals.empty();
  if (!normals.empty() && !theirs) {
    // Give the incoming vertices their faces' geometric normals.
    std::vector<glm::vec3> n(other.positions.size(), glm::vec3(0.0f));
    for (const auto& t : other.triangles) {
      glm::vec3 fn = face_normal(other, t);
      n[t.x] += fn;
      n[t.y] += fn;
      n[t.z] += fn;
    }
    for (auto& v : n) v = glm::length(v) > 0 ? glm::normalize(v) : glm::vec3(0, 1, 0);
    normals.insert(normals.end(), n.begin(), n.end());
  } else if (theirs && normals.empty() && !positions.empty()) {
    compute_vertex_normals(*this);
  }
  const auto offset = static_cast<uint32_t>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  if (theirs) normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles) triangles.push_back(t + glm::uvec3(offset));
}

void compute_vertex_normals(TriangleMesh& mesh) {
  std::vector<glm::vec3> n(mesh.positions.size(), glm::vec3(0.0f));
  for (const auto& t : mesh.triangles) {
    glm::vec3 fn = face_normal(mesh, t);  // length = 2 * area: area weighting for free
    n[t.x] += fn;
    n[t.y] += fn;
    n[t.z] += fn;
  }
  for (auto& v : n) {
    float len = glm::length(v);
    v = len > 0.0f ? v / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  mesh.normals = std::move(n);
}

uint64_t content_hash(const TriangleMesh& mesh) {
  Fnv1a f;
  uint64_t counts[3] = {mesh.positions.size(), mesh.triangles.size(), mesh.normals.size()};
  f.bytes(counts, sizeof(counts));
  f.bytes(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  f.bytes(mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3));
  f.bytes(mesh.normals.data(), mesh.normals.size() * sizeof(glm::vec3));
  return f.h;
}

std::string hash_hex(uint64_t hash) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

void validate_mesh(const TriangleMesh& mesh, const std::string& where) {
  if (mesh.triangles.empty()) throw InputError(where + ": mesh has no triangles");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InputError(where + ": vertex " + std::to_string(i) +
                       " has a non-finite coordinate (NaN or infinity)");
    }
    if (std::fabs(p.x) > kMaxSceneCoordinate || std::fabs(p.y) > kMaxSceneCoordinate ||
        std::fabs(p.z) > kMaxSceneCoordinate) {
      throw InputError(where + ": vertex " + std::to_string(i) +
                       " lies beyond 1e7 scene units from the origin (aoeval traces in 32-bit "
                       "float; scale or re-centre the mesh)");
    }
  }
  const auto n = mesh.positions.size();
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    if (t.x >= n || t.y >= n || t.z >= n) {
      throw InputError(where + ": triangle " + std::to_string(i) + " indexes a vertex beyond " +
                       std::to_string(n));
    }
  }
  if (!mesh.normals.empty() && mesh.normals.size() != n) {
    throw InputError(where + ": " + std::to_string(mesh.normals.size()) + " normals for " +
                     std::to_string(n) + " vertices");
  }
}

}  // namespace aoeval
