// glTF scenes (issue 44): the test scenes of scenes/testdata/gltf: animated.gltf (written by
// make_animated.py, which also computed every node's world matrix per frame in Python:
// animated_expected.json) and blender_animated.glb (written by Blender's exporter,
// make_blender_asset.py, with the matrices Blender evaluated: blender_expected.json).
// Views and sequences, the shared mesh, interpolation, and G-buffer motion vectors against the
// Python poses.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/gltf_animation.h"
#include "scenes/gltf_scene.h"
#include "scenes/instances.h"
#include "scenes/sequence_frame.h"

namespace aoeval {
namespace {

const std::string kDir = std::string(AOEVAL_SOURCE_DIR) + "/scenes/testdata/gltf/";

glm::dmat4 matrix(const nlohmann::json& rows) {  // row-major lists -> glm (column-major)
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c].get<double>();
  return m;
}

TEST(GltfScene, ObjectsViewsAndSequences) {
  const Scene s = load_gltf_scene(kDir + "animated.gltf");
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].name, "floor");
  EXPECT_EQ(s.objects[1].name, "cube");  // the mesh of boxA and boxB
  EXPECT_EQ(s.objects[1].instance_names, (std::vector<std::string>{"boxA", "boxB"}));
  ASSERT_EQ(s.views.size(), 3u);
  EXPECT_EQ(s.views[0].name, "cam");
  EXPECT_FALSE(s.views[0].sequence);
  EXPECT_NEAR(s.views[0].fov_y_deg, 0.8 * 180.0 / M_PI, 1e-4);
  EXPECT_EQ(s.views[1].name, "cam@fly");
  EXPECT_EQ(s.views[1].frame_count(), 61);  // 2 s at 30 fps, both ends
  EXPECT_EQ(s.views[2].name, "cam@hop");
  EXPECT_EQ(s.views[2].frame_count(), 31);
  // "hop" moves only boxA: the camera holds, and boxB keeps an exact identity.
  const SequenceFrame f = sequence_frame(s, s.views[2], 20);
  EXPECT_EQ(f.motion[2], glm::mat4(1.0f));
  EXPECT_NE(f.motion[1], glm::mat4(1.0f));
  EXPECT_EQ(f.view.eye, s.views[0].eye);
}

TEST(GltfScene, SharedMeshIsOneGeometry) {
  const Scene s = load_gltf_scene(kDir + "animated.gltf");
  EXPECT_EQ(s.triangle_count(), 2u + 12u);               // the cube once
  EXPECT_EQ(instanced_triangle_count(s), 2u + 2 * 12u);  // placed twice
  EXPECT_EQ(PlacementIds(s).count, 3u);                  // floor, boxA, boxB
}

TEST(GltfScene, AnObjectOfASceneFile) {
  const auto dir = testutil::test_temp_dir("gltf_entry");
  const std::string path = (dir / "set.json").string();
  std::ofstream(path) << R"({"objects": [{"name": "set", "gltf": ")" << kDir
                      << R"(animated.gltf", "shared_meshes": "copies", "fit": {"size": 2}}],
    "views": [{"name": "v", "eye": [0, 1, 3], "target": [0, 0, 0]}]})";
  const Scene s = load_scene_file(path);
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(s.objects[1].name, "set/boxA");
  EXPECT_EQ(s.objects[2].name, "set/boxB");
  EXPECT_NEAR(s.bounds().extent().x, 2.0f, 1e-5f);  // the 10 m floor fitted to 2
  std::ofstream(path) << R"({"objects": [{"name": "set", "gltf": ")" << kDir << R"(animated.gltf"}],
    "views": [{"name": "v", "eye": [0, 1, 3], "target": [0, 0, 0]}]})";
  const Scene shared = load_scene_file(path);
  ASSERT_EQ(shared.objects.size(), 2u);
  EXPECT_EQ(shared.objects[1].instance_names, (std::vector<std::string>{"set/boxA", "set/boxB"}));
}

TEST(GltfAnimation, StepLinearCubicAndSlerp) {
  GltfChannel c;
  c.path = GltfPath::translation;
  c.times = {0.0, 1.0};
  c.values = {0, 0, 0, 2, 4, 6};
  EXPECT_EQ(sample_channel(c, 0.25), (std::vector<double>{0.5, 1.0, 1.5}));
  EXPECT_EQ(sample_channel(c, -1.0), (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(sample_channel(c, 9.0), (std::vector<double>{2, 4, 6}));
  c.interpolation = GltfInterpolation::step;
  EXPECT_EQ(sample_channel(c, 0.99), (std::vector<double>{0, 0, 0}));
  // Cubic: in-tangent, value, out-tangent per key; p(u) = h00 v0 + h10 td b0 + h01 v1 + h11 td a1.
  c.interpolation = GltfInterpolation::cubic;
  c.times = {0.0, 2.0};
  c.values = {0, 0, 0, 0, 0, 0, 1, 0, 0, /**/ 0, 0, 0, 1, 0, 0, 0, 0, 0};
  // u = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = -0.125; x = 0.125 * 2 * 1 + 0.5 * 1.
  EXPECT_NEAR(sample_channel(c, 1.0)[0], 0.75, 1e-12);
  // Slerp of a 90 degree turn about Y at u = 1/3: exactly 30 degrees (nlerp would give 28.2).
  GltfChannel r;
  r.path = GltfPath::rotation;
  r.times = {0.0, 1.0};
  const double h = M_PI / 4;
  r.values = {0, 0, 0, 1, 0, std::sin(h), 0, std::cos(h)};
  const std::vector<double> q = sample_channel(r, 1.0 / 3.0);
  EXPECT_NEAR(2.0 * std::atan2(q[1], q[3]), M_PI / 6, 1e-12);
}

struct Pinhole {
  glm::dvec3 eye, forward, right, up;
  double tan_half, width, height;
  glm::dvec2 project(const glm::dvec3& p) const {
    const glm::dvec3 v = p - eye;
    const double z = glm::dot(v, forward);
    const double x = glm::dot(v, right) / (z * tan_half * width / height);
    const double y = glm::dot(v, up) / (z * tan_half);
    return {0.5 * (x + 1.0) * width, 0.5 * (1.0 - y) * height};
  }
};

Pinhole pinhole(const glm::dmat4& w, double yfov, int width, int height) {
  Pinhole c;
  c.eye = glm::dvec3(w[3]);
  c.forward = glm::normalize(-glm::dvec3(w[2]));
  c.up = glm::normalize(glm::dvec3(w[1]));
  c.right = glm::normalize(glm::cross(c.forward, c.up));
  c.tan_half = std::tan(0.5 * yfov);
  c.width = width;
  c.height = height;
  return c;
}

// A glTF asset and the poses its generator computed on its own: each node's world matrix per frame.
struct PosedAsset {
  std::string gltf, expected;
  std::vector<int> node_of;  // placement id (floor, boxA, boxB) -> index in the expected nodes
  int camera, moving;        // the camera's and the moving box's index there
};
const PosedAsset kPython{"animated.gltf", "animated_expected.json", {0, 1, 3}, 4, 3};
// Written by Blender 3.4 (make_blender_asset.py): matrices as Blender evaluates them.
const PosedAsset kBlender{"blender_animated.glb", "blender_expected.json", {0, 1, 2}, 3, 2};

// Motion of every covered pixel of frame k against the generator's poses: the surface point P_k is
// taken into its node's space with frame k's world matrix and back out with frame k - 1's, and
// both are projected through the generator's cameras.
void check_motion(const PosedAsset& a, const std::string& animation, int k, double& worst,
                  size_t& moving) {
  const Scene s = load_gltf_scene(kDir + a.gltf);
  std::ifstream in(kDir + a.expected);
  const nlohmann::json e = nlohmann::json::parse(in);
  const View& view = s.view("cam@" + animation);
  const GBuffer g = render_frame_gbuffer(s, view, k, 320, 240);
  ASSERT_EQ(g.motion.size(), g.pixel_count());
  const auto& frames = e["animations"][animation];
  const double yfov = e["yfov"].get<double>();
  const Pinhole now = pinhole(matrix(frames[k]["world"][a.camera]), yfov, 320, 240);
  const Pinhole before = pinhole(matrix(frames[k - 1]["world"][a.camera]), yfov, 320, 240);
  size_t checked = 0;
  for (size_t p = 0; p < g.pixel_count(); ++p) {
    if (!g.covered(p)) continue;
    const int node = a.node_of.at(static_cast<size_t>(g.object_id[p]));
    const glm::dvec3 pk(g.position[p]);
    const glm::dvec4 local = glm::inverse(matrix(frames[k]["world"][node])) * glm::dvec4(pk, 1.0);
    const glm::dvec3 prev(matrix(frames[k - 1]["world"][node]) * local);
    const glm::dvec2 want = now.project(pk) - before.project(prev);
    const double err = glm::length(want - glm::dvec2(g.motion[p]));
    worst = std::max(worst, err);
    if (glm::length(want) > 0.05 && node == a.moving) ++moving;
    ++checked;
  }
  EXPECT_GT(checked, 10000u);
}

TEST(GltfScene, MotionVectorsAgreeWithIndependentPoses) {
  double worst = 0.0;
  size_t moving_box = 0;
  for (int k : {1, 16, 30, 45, 60}) check_motion(kPython, "fly", k, worst, moving_box);
  for (int k : {15, 16}) check_motion(kPython, "hop", k, worst, moving_box);
  std::printf("worst motion difference %.3g px; %zu moving boxB pixels\n", worst, moving_box);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(moving_box, 1000u);  // boxB (instanced, under the turning rig) is seen moving
}

// Must-show 1 with Blender: its exporter's .glb (camera and object animation, a linked duplicate)
// against the matrices Blender itself evaluated, turned to glTF's Y up (make_blender_asset.py).
TEST(GltfScene, BlenderAssetMotionAgreesWithBlendersOwnMatrices) {
  const Scene s = load_gltf_scene(kDir + kBlender.gltf);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[1].name, "cube");  // one mesh for boxA and its linked duplicate boxB
  EXPECT_EQ(s.objects[1].instance_names, (std::vector<std::string>{"boxA", "boxB"}));
  EXPECT_EQ(s.view("cam@Animation").frame_count(), 61);
  double worst = 0.0;
  size_t moving_box = 0;
  for (int k : {1, 10, 30, 41, 60}) check_motion(kBlender, "Animation", k, worst, moving_box);
  std::printf("Blender asset: worst motion difference %.3g px; %zu moving boxB pixels\n", worst,
              moving_box);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(moving_box, 1000u);
}

// The bad inputs of issue 44, each named by its glTF path.
std::string load_error(const std::string& patch_name, const nlohmann::json& doc) {
  const auto dir = testutil::test_temp_dir("gltf_bad");
  const std::string path = (dir / (patch_name + ".gltf")).string();
  std::ofstream(path) << doc.dump();
  try {
    load_gltf_scene(path);
  } catch (const InputError& err) {
    return err.what();
  }
  return "";
}

TEST(GltfScene, BadInputNamesTheGltfPath) {
  std::ifstream in(kDir + "animated.gltf");
  const nlohmann::json good = nlohmann::json::parse(in);
  nlohmann::json d = good;
  d["buffers"][0]["uri"] = "missing.bin";
  EXPECT_NE(load_error("buffer", d).find("buffers[0].uri: buffer file"), std::string::npos);
  d = good;
  d["meshes"][0]["primitives"][0]["mode"] = 1;
  EXPECT_NE(load_error("lines", d).find("meshes[0].primitives[0].mode: mode 1 is not triangles"),
            std::string::npos);
  d = good;
  const size_t input = d["animations"][1]["samplers"][0]["input"].get<size_t>();
  d["accessors"][input]["count"] = 0;
  EXPECT_NE(load_error("nokeys", d).find("animations[1].channels[0]: its sampler has no keys"),
            std::string::npos);
  d = good;
  d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, nullptr, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_NE(load_error("nan", d).find("nodes[0].matrix: element 5 is not a finite number"),
            std::string::npos);
  d = good;
  d["nodes"][4]["translation"] = {-1.2, 0.5, 0.1};  // inside boxA
  EXPECT_NE(load_error("inside", d).find("nodes[4]: camera 'cam' is inside geometry"),
            std::string::npos);
  d = good;
  d["cameras"][0] = {{"type", "orthographic"},
                     {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 9}}}};
  EXPECT_NE(load_error("ortho", d).find("cameras[0]: orthographic camera"), std::string::npos);
  EXPECT_EQ(load_error("good", good), "");
}

}  // namespace
}  // namespace aoeval
