// Scene files: parsing, validation messages that name the file and the field, placement, and the
// corpus of CONTRACT §6.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/corpus.h"
#include "scenes/scene.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

class SceneFileTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = aoeval::testutil::test_temp_dir("scene"); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  // Expects load_scene_file to fail with a message containing every one of `parts`.
  void expect_error(const std::string& path, std::vector<std::string> parts) {
    try {
      load_scene_file(path);
      FAIL() << "no error for " << path;
    } catch (const InputError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
      for (const auto& p : parts)
        EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
  }
  fs::path dir_;
};

const char* kView = R"("views": [{"name": "main", "eye": [0, 1, 3], "target": [0, 0, 0]}])";

TEST_F(SceneFileTest, LoadsGeneratorsTransformsAndViews) {
  std::string path = write("s.json", std::string(R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [2, 4]}, "role": "ground",
       "transform": {"translate": [1, 2, 3], "scale": [2, 1, 1]}}], )") +
                                         kView + "}");
  Scene s = load_scene_file(path);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].role, Role::ground);
  Bounds b = s.bounds();
  EXPECT_NEAR(b.lower.x, 1 - 2, 1e-6);
  EXPECT_NEAR(b.upper.x, 1 + 2, 1e-6);
  EXPECT_NEAR(b.lower.y, 2, 1e-6);
  EXPECT_NEAR(b.lower.z, 3 - 2, 1e-6);
  EXPECT_EQ(s.views[0].name, "main");
  EXPECT_EQ(s.views[0].width, 320);
  EXPECT_EQ(&s.view(""), &s.views[0]);
  EXPECT_THROW(s.view("nope"), InputError);
}

TEST_F(SceneFileTest, FitScalesToSizeAndRestsOnGround) {
  write("m.off", "OFF\n4 2 0\n10 10 10\n12 10 10\n12 14 10\n10 14 10\n3 0 1 2\n3 0 2 3\n");
  std::string path = write("s.json", std::string(R"({"objects": [
      {"name": "m", "mesh": "m.off", "fit": {"size": 1.0}}], )") +
                                         kView + "}");
  Scene s = load_scene_file(path);
  Bounds b = s.bounds();
  EXPECT_NEAR(b.extent().y, 1.0f, 1e-6);
  EXPECT_NEAR(b.extent().x, 0.5f, 1e-6);
  EXPECT_NEAR(b.lower.y, 0.0f, 1e-6);
  EXPECT_NEAR(b.center().x, 0.0f, 1e-6);
}

TEST_F(SceneFileTest, ProxyFollowsTheObjectTransform) {
  std::string path = write("s.json", std::string(R"({"objects": [
      {"name": "t", "generator": "sphere", "role": "tree", "density": 40,
       "proxy": {"type": "ellipsoid", "center": [0, 1, 0], "radii": [1, 2, 1]},
       "transform": {"translate": [5, 0, 0], "scale": [2, 2, 2], "rotate_deg": [0, 0, 90]}}], )") +
                                         kView + "}");
  Scene s = load_scene_file(path);
  const auto& e = s.objects[0].proxy->shapes[0];
  EXPECT_NEAR(e.center.x, 5 - 2, 1e-5);  // (0,1,0) scaled to (0,2,0), rotated 90 deg about Z
  EXPECT_NEAR(e.center.y, 0, 1e-5);
  EXPECT_NEAR(e.radii.y, 4, 1e-5);
  EXPECT_NEAR(std::abs(e.axes[1].x), 1, 1e-5);  // the long axis now lies along X
  EXPECT_DOUBLE_EQ(*s.objects[0].density, 40);
}

TEST_F(SceneFileTest, MisspelledKeyNamesFileAndField) {
  std::string path = write("typo.json", std::string(R"({"objects": [
      {"name": "p", "generator": "plane", "trnsform": {}}], )") +
                                            kView + "}");
  expect_error(path, {"typo.json", "objects[0].trnsform", "unknown key"});
}

TEST_F(SceneFileTest, MisspelledGeneratorParamNamesIt) {
  std::string path = write("p.json", std::string(R"({"objects": [
      {"name": "p", "generator": "plane", "params": {"sise": [1, 1]}}], )") +
                                         kView + "}");
  expect_error(path, {"p.json", "objects[0].params.sise", "unknown key"});
}

TEST_F(SceneFileTest, MissingMeshNamesFileAndField) {
  std::string path = write("missing.json", std::string(R"({"objects": [
      {"name": "m", "mesh": "nowhere.obj"}], )") +
                                               kView + "}");
  expect_error(path, {"missing.json", "objects[0].mesh", "nowhere.obj", "not found"});
}

TEST_F(SceneFileTest, NaNCoordinatesNameFileAndField) {
  write("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  std::string path = write("nan.json", std::string(R"({"objects": [
      {"name": "m", "mesh": "nan.off"}], )") +
                                           kView + "}");
  expect_error(path, {"nan.json", "objects[0].mesh", "nan.off", "vertex 1", "non-finite"});
}

TEST_F(SceneFileTest, ZeroWidthViewNamesFileAndField) {
  std::string path = write("view.json", R"({"objects": [{"name": "p", "generator": "plane"}],
      "views": [{"name": "v", "eye": [0, 1, 3], "target": [0, 0, 0], "width": 0}]})");
  expect_error(path, {"view.json", "views[0].width", "out of range"});
}

TEST_F(SceneFileTest, OtherBadInputs) {
  expect_error(write("a.json", "{\"objects\": [}"), {"a.json:1:", "invalid JSON"});
  expect_error(
      write("b.json",
            std::string(R"({"objects": [{"name": "p", "generator": "nope"}], )") + kView + "}"),
      {"b.json", "objects[0].generator", "unknown generator"});
  expect_error(
      write("c.json",
            std::string(R"({"objects": [{"name": "p", "generator": "plane", "role": "rock"}], )") +
                kView + "}"),
      {"c.json", "objects[0].role", "rock"});
  expect_error(
      write("d.json", R"({"objects": [{"name": "p", "generator": "plane"}], "views": []})"),
      {"d.json", "views", "at least 1"});
  expect_error(write("e.json", R"({"objects": [{"name": "p", "generator": "plane"}],
      "views": [{"name": "v", "eye": [0, 0, 0], "target": [0, 0, 0]}]})"),
               {"e.json", "views[0].target"});
  expect_error(
      write(
          "f.json",
          std::string(
              R"({"objects": [{"name": "p", "generator": "plane", "proxy": {"type": "sphere", "center": [0,0,0], "radius": 1}}], )") +
              kView + "}"),
      {"f.json", "objects[0].proxy", "tree"});
  expect_error(
      write("g.json",
            std::string(R"({"objects": [{"name": "p", "mesh": "x.off", "generator": "plane"}], )") +
                kView + "}"),
      {"g.json", "objects[0]", "exactly one"});
  expect_error(
      write(
          "h.json",
          std::string(
              R"({"objects": [{"name": "p", "generator": "plane", "transform": {"scale": [1, 0, 1]}}], )") +
              kView + "}"),
      {"h.json", "objects[0].transform.scale"});
}

TEST(Corpus, HasEveryContractNameWithTwoViewsAndLoadsDeterministically) {
  const std::vector<std::string> contract = {"sphere-uniform", "sphere-uniform-dense",
                                             "tree-apple",     "tree-poplar",
                                             "tree-ground",    "grass-field",
                                             "ecosystem",      "cornell-box",
                                             "room",           "bunny",
                                             "dragon",         "armadillo",
                                             "elephant"};
  const auto names = corpus_names();
  for (const auto& n : contract)
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  for (const auto& n : names) {
    if (n == "ecosystem")
      continue;  // its size is checked by the CLI test; loading it twice is slow
    Scene a = load_scene(n);
    EXPECT_GE(a.views.size(), 2u) << n;
    EXPECT_GT(a.triangle_count(), 0u) << n;
    Scene b = load_scene(n);
    EXPECT_EQ(a.content_hash(), b.content_hash()) << n << " is not deterministic";
  }
}

TEST(Corpus, UnknownNameListsTheCorpus) {
  try {
    load_scene("no-such-scene");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bunny"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aoeval
