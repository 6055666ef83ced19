// Mesh loading: the strict OFF reader and assimp for the rest.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/mesh_io.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

std::string write_temp(const std::string& name, const std::string& text) {
  fs::path p = aoeval::testutil::test_temp_dir("mesh_io") / name;
  std::ofstream(p) << text;
  return p.string();
}

TEST(MeshIo, OffWithCommentsQuadsAndColours) {
  auto path = write_temp(
      "quad.off", "OFF\n# a unit quad\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n");
  TriangleMesh m = load_mesh(path);
  EXPECT_EQ(m.triangle_count(), 2u);
  ASSERT_EQ(m.normals.size(), 4u);
  EXPECT_NEAR(m.normals[0].z, 1.0f, 1e-6);
}

TEST(MeshIo, OffErrorsNameTheLine) {
  try {
    load_mesh(write_temp("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
    FAIL();
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("bad.off:6"), std::string::npos) << msg;
    EXPECT_NE(msg.find("vertex 7"), std::string::npos) << msg;
  }
  EXPECT_THROW(load_mesh(write_temp("trunc.off", "OFF\n3 1 0\n0 0 0\n")), InputError);
  EXPECT_THROW(load_mesh(write_temp("hdr.off", "PLY\n")), InputError);
  EXPECT_THROW(load_mesh(write_temp("inf.off", "OFF\n3 1 0\n0 0 inf\n1 0 0\n0 1 0\n3 0 1 2\n")),
               InputError);
}

TEST(MeshIo, ObjThroughAssimp) {
  auto path = write_temp("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n");
  TriangleMesh m = load_mesh(path);
  EXPECT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.normals.size(), m.positions.size());
}

TEST(MeshIo, MissingAndUnreadableFiles) {
  EXPECT_THROW(load_mesh("/nonexistent/mesh.obj"), InputError);
  EXPECT_THROW(load_mesh(write_temp("junk.obj", "this is not a mesh\n")), InputError);
}

TEST(MeshIo, AssimpTestModelLoads) {
  const std::string wuson = "/usr/share/assimp/models/OBJ/WusonOBJ.obj";
  if (!fs::exists(wuson)) GTEST_SKIP() << "assimp-testmodels not installed";
  TriangleMesh m = load_mesh(wuson);
  EXPECT_GT(m.triangle_count(), 1000u);
}

}  // namespace
}  // namespace aoeval
