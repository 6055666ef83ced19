#include "scenes/scene_export.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <stdexcept>

#include "base/errors.h"
#include "base/text_files.h"

namespace aoeval {

namespace {

void append_bytes(std::string& out, const void* data, size_t n) {
  out.append(static_cast<const char*>(data), n);
}

// One placement of a mesh: its positions through `m` (identity for a plain object).
void append_placed(const TriangleMesh& mesh, const glm::mat4& m, uint64_t first_vertex,
                   std::string& vertices, std::string& faces) {
  for (const auto& p : mesh.positions) {
    const glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
    append_bytes(vertices, &w, sizeof(float) * 3);
  }
  for (const auto& t : mesh.triangles) {
    const uint8_t n = 3;
    append_bytes(faces, &n, 1);
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = static_cast<uint32_t>(first_vertex + t[k]);
      append_bytes(faces, &index, sizeof(index));
    }
  }
}

nlohmann::json vec3(const glm::vec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

void write_scene_ply(const Scene& scene, const std::string& path) {
  static_assert(std::numeric_limits<float>::is_iec559);
  std::string vertices, faces;
  uint64_t vertex_count = 0, face_count = 0;
  for (const auto& o : scene.objects) {
    const std::vector<glm::mat4> placements =
        o.instances.empty() ? std::vector<glm::mat4>{glm::mat4(1.0f)} : o.instances;
    for (const auto& m : placements) {
      append_placed(o.mesh, m, vertex_count, vertices, faces);
      vertex_count += o.mesh.positions.size();
      face_count += o.mesh.triangles.size();
    }
  }
  if (vertex_count > std::numeric_limits<uint32_t>::max())
    throw InputError(path + ": the scene has " + std::to_string(vertex_count) +
                     " placed vertices, more than a PLY with uint indices holds");
  const std::string header = "ply\nformat binary_little_endian 1.0\ncomment aoeval scene " +
                             scene.name + "\nelement vertex " + std::to_string(vertex_count) +
                             "\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face " +
                             std::to_string(face_count) +
                             "\nproperty list uchar uint vertex_indices\nend_header\n";
  const std::string temporary = temporary_path_for(path);
  {
    std::ofstream out(temporary, std::ios::binary);
    out << header;
    out.write(vertices.data(), static_cast<std::streamsize>(vertices.size()));
    out.write(faces.data(), static_cast<std::streamsize>(faces.size()));
    if (!out.flush()) {
      discard_temporary(temporary);
      throw std::runtime_error(path + ": cannot write the PLY file");
    }
  }
  commit_temporary(temporary, path);
}

nlohmann::json camera_to_json(const Scene& scene, const View& view, const Camera& camera) {
  return {{"scene", scene.name},
          {"view", view.name},
          {"eye", vec3(camera.eye)},
          {"forward", vec3(camera.forward)},
          {"right", vec3(camera.right)},
          {"up", vec3(camera.up)},
          {"fov_y_deg", view.fov_y_deg},
          {"tan_half_fov_y", camera.tan_half_fov_y},
          {"width", camera.width},
          {"height", camera.height},
          {"pixel_centre", "pixel (i, j) is sampled at (i + 0.5, j + 0.5); row 0 is the top"},
          {"world", "right-handed, +Y up"}};
}

}  // namespace aoeval
