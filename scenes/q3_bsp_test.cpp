// Quake 3 BSP levels (issue 44): a hand-made IBSP 46 file with a polygon face, a sky face and a
// flat 3 x 3 Bezier patch, and malformed files.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/q3_bsp.h"

namespace aoeval {
namespace {

struct Bsp {
  std::string lumps[17];
  template <typename T>
  static void put(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void vertex(glm::vec3 p, glm::vec3 n) {
    std::string& s = lumps[10];
    for (float f : {p.x, p.y, p.z, 0.f, 0.f, 0.f, 0.f, n.x, n.y, n.z}) put(s, f);
    put(s, uint32_t(0));
  }
  void face(int texture, int type, int first, int count, int mv, int n_mv, int w = 0, int h = 0) {
    std::string& s = lumps[13];
    for (int v : {texture, 0, type, first, count, mv, n_mv, 0, 0, 0, 0, 0}) put(s, int32_t(v));
    for (int i = 0; i < 12; ++i) put(s, 0.0f);
    put(s, int32_t(w));
    put(s, int32_t(h));
  }
  void texture(const char* name, int flags) {
    std::string& s = lumps[1];
    std::string n(64, '\0');
    std::memcpy(n.data(), name, std::strlen(name));
    s += n;
    put(s, int32_t(flags));
    put(s, int32_t(0));
  }
  std::string write(const std::string& name) const {
    std::string out = "IBSP";
    put(out, int32_t(46));
    size_t offset = 8 + 17 * 8;
    for (const auto& l : lumps) {
      put(out, int32_t(offset));
      put(out, int32_t(l.size()));
      offset += l.size();
    }
    for (const auto& l : lumps) out += l;
    const std::string path = (testutil::test_temp_dir("q3_bsp") / name).string();
    std::ofstream(path, std::ios::binary) << out;
    return path;
  }
};

Bsp level() {
  Bsp b;
  b.texture("textures/base/floor", 0);
  b.texture("textures/skies/blue", 0x4);
  // Face 0: a floor quad (Z up) wound clockwise seen from above: it is turned to face up.
  const glm::vec3 up(0, 0, 1);
  for (glm::vec3 p :
       {glm::vec3(0, 0, 0), glm::vec3(0, 1, 0), glm::vec3(1, 1, 0), glm::vec3(1, 0, 0)})
    b.vertex(p, up);
  for (int32_t i : {0, 1, 2, 0, 2, 3}) Bsp::put(b.lumps[11], i);
  b.face(0, 1, 0, 4, 0, 6);
  b.face(1, 1, 0, 4, 0, 6);  // the same quad as sky: left out
  // Face 2: a flat 3 x 3 patch at z = 2.
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) b.vertex(glm::vec3(i, j, 2), up);
  b.face(0, 2, 4, 9, 0, 0, 3, 3);
  return b;
}

TEST(Q3Bsp, FacesSkyAndPatches) {
  const TriangleMesh m = load_q3_bsp(level().write("ok.bsp"));
  EXPECT_EQ(m.triangle_count(), 2u + 2u * 8u * 8u);  // the quad, the patch's 8 x 8 quads
  for (const auto& t : m.triangles) {
    const glm::vec3 n =
        glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    EXPECT_GT(n.z, 0.0f);  // every triangle faces its vertex normals
  }
  EXPECT_FLOAT_EQ(m.bounds().upper.z, 2.0f);
  EXPECT_FLOAT_EQ(m.bounds().upper.x, 2.0f);
}

TEST(Q3Bsp, MalformedFilesAreInputErrors) {
  Bsp b = level();
  b.lumps[11].resize(8);  // mesh vertices cut short
  EXPECT_THROW(load_q3_bsp(b.write("short.bsp")), InputError);
  b = level();
  b.face(0, 2, 4, 9, 0, 0, 2, 3);  // an even patch width
  try {
    load_q3_bsp(b.write("patch.bsp"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("faces[3]: a patch of 2 x 3"), std::string::npos)
        << e.what();
  }
  const std::string path = (testutil::test_temp_dir("q3_bsp") / "not.bsp").string();
  std::ofstream(path) << "VBSP";
  EXPECT_THROW(load_q3_bsp(path), InputError);
}

}  // namespace
}  // namespace aoeval
