#include "scenes/q3_bsp.h"

#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <sstream>
#include <vector>

#include "base/errors.h"

namespace aoeval {

namespace {

constexpr int kTextures = 1, kVertexes = 10, kMeshVerts = 11, kFaces = 13;
constexpr size_t kTextureBytes = 72, kVertexBytes = 44, kFaceBytes = 104;
constexpr int kSurfSky = 0x4, kSurfNoDraw = 0x80;
constexpr int kPatchSteps = 8;

struct Reader {
  std::string path;
  std::string bytes;
  [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }
  int32_t i32(size_t at) const {
    int32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  }
  float f32(size_t at) const {
    float v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  }
  // Lump `l`: its offset and element count, checked to lie in the file.
  std::pair<size_t, size_t> lump(int l, size_t element) const {
    const int32_t offset = i32(8 + 8 * l), length = i32(12 + 8 * l);
    if (offset < 0 || length < 0 || static_cast<size_t>(offset) + length > bytes.size() ||
        length % element != 0)
      fail("lump " + std::to_string(l) + " lies outside the file or is not whole records");
    return {static_cast<size_t>(offset), static_cast<size_t>(length) / element};
  }
};

struct Vertex {
  glm::vec3 p, n;
};

Vertex bezier(const Vertex c[9], float u, float v) {
  const float bu[3] = {(1 - u) * (1 - u), 2 * u * (1 - u), u * u};
  const float bv[3] = {(1 - v) * (1 - v), 2 * v * (1 - v), v * v};
  Vertex out{glm::vec3(0.0f), glm::vec3(0.0f)};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      out.p += bu[i] * bv[j] * c[j * 3 + i].p;
      out.n += bu[i] * bv[j] * c[j * 3 + i].n;
    }
  return out;
}

}  // namespace

TriangleMesh load_q3_bsp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open level file");
  std::ostringstream ss;
  ss << in.rdbuf();
  Reader r{path, ss.str()};
  if (r.bytes.size() < 8 + 17 * 8 || r.bytes.compare(0, 4, "IBSP") != 0 || r.i32(4) != 46)
    r.fail("not a Quake 3 BSP (IBSP version 46) file");
  const auto [tex_at, tex_n] = r.lump(kTextures, kTextureBytes);
  const auto [vert_at, vert_n] = r.lump(kVertexes, kVertexBytes);
  const auto [mv_at, mv_n] = r.lump(kMeshVerts, 4);
  const auto [face_at, face_n] = r.lump(kFaces, kFaceBytes);
  std::vector<Vertex> verts(vert_n);
  for (size_t i = 0; i < vert_n; ++i) {
    const size_t at = vert_at + i * kVertexBytes;
    verts[i].p = {r.f32(at), r.f32(at + 4), r.f32(at + 8)};
    verts[i].n = {r.f32(at + 28), r.f32(at + 32), r.f32(at + 36)};
  }
  TriangleMesh mesh;
  auto add_triangle = [&](const Vertex& a, const Vertex& b, const Vertex& c) {
    const glm::vec3 ng = glm::cross(b.p - a.p, c.p - a.p);
    const bool flip = glm::dot(ng, a.n + b.n + c.n) < 0.0f;
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (const Vertex* v : {&a, flip ? &c : &b, flip ? &b : &c}) mesh.positions.push_back(v->p);
    mesh.triangles.emplace_back(base, base + 1, base + 2);
  };
  for (size_t f = 0; f < face_n; ++f) {
    const size_t at = face_at + f * kFaceBytes;
    const std::string where = "faces[" + std::to_string(f) + "]";
    const int32_t texture = r.i32(at), type = r.i32(at + 8);
    const int32_t first = r.i32(at + 12), count = r.i32(at + 16);
    if (texture >= 0 && static_cast<size_t>(texture) < tex_n &&
        (r.i32(tex_at + texture * kTextureBytes + 64) & (kSurfSky | kSurfNoDraw)))
      continue;
    if (first < 0 || count < 0 || static_cast<size_t>(first) + count > vert_n)
      r.fail(where + ": vertices outside the vertex lump");
    if (type == 1 || type == 3) {
      const int32_t mv = r.i32(at + 20), n_mv = r.i32(at + 24);
      if (mv < 0 || n_mv < 0 || n_mv % 3 != 0 || static_cast<size_t>(mv) + n_mv > mv_n)
        r.fail(where + ": mesh vertices outside their lump");
      for (int32_t k = 0; k < n_mv; k += 3) {
        int32_t idx[3];
        for (int c = 0; c < 3; ++c) {
          idx[c] = r.i32(mv_at + 4 * (mv + k + c));
          if (idx[c] < 0 || idx[c] >= count) r.fail(where + ": a mesh vertex outside its face");
        }
        add_triangle(verts[first + idx[0]], verts[first + idx[1]], verts[first + idx[2]]);
      }
    } else if (type == 2) {
      const int32_t w = r.i32(at + 96), h = r.i32(at + 100);
      if (w < 3 || h < 3 || w % 2 == 0 || h % 2 == 0 || w * h != count)
        r.fail(where + ": a patch of " + std::to_string(w) + " x " + std::to_string(h) +
               " control points");
      for (int py = 0; py + 2 < h; py += 2)
        for (int px = 0; px + 2 < w; px += 2) {
          Vertex c[9];
          for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) c[j * 3 + i] = verts[first + (py + j) * w + px + i];
          std::vector<Vertex> grid;
          for (int j = 0; j <= kPatchSteps; ++j)
            for (int i = 0; i <= kPatchSteps; ++i)
              grid.push_back(bezier(c, float(i) / kPatchSteps, float(j) / kPatchSteps));
          const int row = kPatchSteps + 1;
          for (int j = 0; j < kPatchSteps; ++j)
            for (int i = 0; i < kPatchSteps; ++i) {
              const Vertex& a = grid[j * row + i];
              const Vertex& b = grid[j * row + i + 1];
              const Vertex& d = grid[(j + 1) * row + i];
              const Vertex& e = grid[(j + 1) * row + i + 1];
              add_triangle(a, b, e);
              add_triangle(a, e, d);
            }
        }
    }
  }
  // Degenerate patch quads (collapsed control rows) make zero-area triangles: dropped.
  TriangleMesh out;
  out.positions = std::move(mesh.positions);
  for (const auto& t : mesh.triangles) {
    const glm::vec3 e = glm::cross(out.positions[t.y] - out.positions[t.x],
                                   out.positions[t.z] - out.positions[t.x]);
    if (glm::dot(e, e) > 0.0f) out.triangles.push_back(t);
  }
  validate_mesh(out, path);
  return out;
}

}  // namespace aoeval
