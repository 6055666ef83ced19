// `aoeval scenes export` (scenes/scene_export.h): the PLY holds every placement of an instanced
// object, transformed, with its indices offset; the camera JSON is make_camera's basis.
#include "scenes/scene_export.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <iterator>

#include "base/testing/test_temp_dir.h"

namespace aoeval {
namespace {

TEST(SceneExport, PlyPlacesEveryInstance) {
  Scene s;
  s.name = "t";
  SceneObject plain;
  plain.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  plain.mesh.triangles = {{0, 1, 2}};
  SceneObject inst = plain;
  inst.instances = {glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 5)),
                    glm::scale(glm::mat4(1.0f), glm::vec3(2.0f))};
  s.objects = {plain, inst};
  const std::string path = (testutil::test_temp_dir("export") / "t.ply").string();
  write_scene_ply(s, path);
  std::ifstream in(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t end = data.find("end_header\n") + 11;
  ASSERT_NE(data.find("element vertex 9\n"), std::string::npos);
  ASSERT_NE(data.find("element face 3\n"), std::string::npos);
  ASSERT_EQ(data.size(), end + 9 * 12 + 3 * 13);
  float v[27];
  std::memcpy(v, data.data() + end, sizeof(v));
  EXPECT_EQ(v[3 * 3 + 2], 5.0f);  // vertex 3: the first instance's (0, 0, 0) moved to z = 5
  EXPECT_EQ(v[3 * 7 + 0], 2.0f);  // vertex 7: the second instance's (1, 0, 0) scaled by 2
  uint32_t last[3];
  std::memcpy(last, data.data() + end + 9 * 12 + 2 * 13 + 1, sizeof(last));
  EXPECT_EQ(last[0], 6u);
  EXPECT_EQ(last[2], 8u);
}

TEST(SceneExport, CameraIsMakeCamerasBasis) {
  Scene s;
  View v;
  v.name = "v";
  v.eye = {1, 2, 3};
  v.target = {1, 2, 0};
  v.fov_y_deg = 60;
  const Camera c = make_camera(v, 64, 48);
  const nlohmann::json j = camera_to_json(s, v, c);
  EXPECT_EQ(j["forward"], (nlohmann::json{0.0f, 0.0f, -1.0f}));
  EXPECT_EQ(j["right"], (nlohmann::json{1.0f, 0.0f, 0.0f}));
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["height"], 48);
  EXPECT_FLOAT_EQ(j["tan_half_fov_y"].get<float>(), c.tan_half_fov_y);
}

}  // namespace
}  // namespace aoeval
