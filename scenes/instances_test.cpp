// Instanced objects (issue 45): loading, bad input, memory guard, ids, and the G-buffer of an
// instanced forest against the same forest written as copies, to the bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"
#include "scenes/instances.h"
#include "scenes/sequence_frame.h"
#include "scenes/testing_forest.h"

namespace aoeval {
namespace {

std::string write_small_forest_for_test() {
  return testutil::write_small_forest(testutil::test_temp_dir("forest"));
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

std::string load_error(const std::string& scene_text) {
  const auto dir = testutil::test_temp_dir("instances");
  const std::string path = (dir / "bad.json").string();
  std::ofstream(path) << scene_text;
  try {
    load_scene_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string with_instances(const std::string& instances) {
  return R"({"objects": [{"name": "ball", "generator": "sphere", "params": {"subdivisions": 1},
             "instances": )" +
         instances + R"(}],
  "views": [{"name": "v", "eye": [0, 0, 5], "target": [0, 0, 0]}]})";
}

TEST(Instances, ForestLoadsWithEveryPlacement) {
  const Scene s = load_scene_file(write_small_forest_for_test());
  ASSERT_EQ(s.objects.size(), 4u);
  // The two shares of the 12 cells together place every cell exactly once.
  EXPECT_EQ(s.objects[1].instances.size() + s.objects[2].instances.size(), 12u);
  EXPECT_GT(s.objects[1].instances.size(), 0u);
  EXPECT_GT(s.objects[2].instances.size(), 0u);
  EXPECT_EQ(s.objects[3].instances.size(), 3u);
  EXPECT_EQ(instance_count(s), 15u);
  size_t placed = s.objects[0].mesh.triangle_count();
  for (size_t i = 1; i < 4; ++i)
    placed += s.objects[i].mesh.triangle_count() * s.objects[i].instances.size();
  EXPECT_EQ(instanced_triangle_count(s), placed);
  EXPECT_LT(s.triangle_count(), placed);
  // Placements sit inside the placer's 8 x 6 rectangle, scaled within [0.8, 1.25].
  for (const glm::mat4& m : s.objects[1].instances) {
    EXPECT_LE(std::fabs(m[3].x), 4.0f);
    EXPECT_LE(std::fabs(m[3].z), 3.0f);
    const float scale = glm::length(glm::vec3(m[1]));
    EXPECT_GE(scale, 0.8f - 1e-5f);
    EXPECT_LE(scale, 1.25f + 1e-5f);
  }
  // Same file, same placements (deterministic placer).
  const Scene again = load_scene_file(write_small_forest_for_test());
  EXPECT_EQ(s.content_hash(), again.content_hash());
}

// The poisson-disk placer: two shares of one placer place every one of `count` spots once,
// inside the rectangle, no two closer than spacing x sqrt(area / count), deterministically; a
// spacing dart throwing cannot reach is one clear line.
TEST(Instances, PoissonDiskPlacerKeepsItsSpacing) {
  const std::string placer =
      R"({"placer": "poisson-disk", "seed": 3, "count": 400, "size": [40, 20], "spacing": 0.7,
          "share": [K, 2], "scale": [0.9, 1.1]})";
  std::string both = placer;
  both.replace(both.find('K'), 1, "0");
  std::string other = placer;
  other.replace(other.find('K'), 1, "1");
  const std::string text =
      R"({"objects": [{"name": "a", "generator": "sphere", "params": {"subdivisions": 1},
          "instances": )" +
      both + R"(}, {"name": "b", "generator": "sphere",
          "params": {"subdivisions": 1}, "instances": )" +
      other + R"(}],
      "views": [{"name": "v", "eye": [0, 0, 5], "target": [0, 0, 0]}]})";
  const auto dir = testutil::test_temp_dir("poisson");
  const std::string path = (dir / "poisson.json").string();
  std::ofstream(path) << text;
  const Scene s = load_scene_file(path);
  std::vector<glm::vec3> spots;
  for (const auto& o : s.objects)
    for (const glm::mat4& m : o.instances) spots.emplace_back(m[3]);
  ASSERT_EQ(spots.size(), 400u);
  EXPECT_GT(s.objects[0].instances.size(), 150u);
  const float r = 0.7f * std::sqrt(40.0f * 20.0f / 400.0f);
  float closest = std::numeric_limits<float>::max();
  for (size_t i = 0; i < spots.size(); ++i) {
    EXPECT_LE(std::fabs(spots[i].x), 20.0f);
    EXPECT_LE(std::fabs(spots[i].z), 10.0f);
    for (size_t j = 0; j < i; ++j) closest = std::min(closest, glm::length(spots[i] - spots[j]));
  }
  EXPECT_GE(closest, r * (1.0f - 1e-5f));
  EXPECT_LE(closest, 1.5f * r);  // dart throwing packs: the bound is met, not far exceeded
  EXPECT_EQ(s.content_hash(), load_scene_file(path).content_hash());
  EXPECT_NE(load_error(with_instances(R"({"placer": "poisson-disk", "count": 50, "spacing": 0.9})"))
                .find("instances.spacing"),
            std::string::npos);
  EXPECT_NE(load_error(with_instances(R"({"placer": "poisson-disk", "count": 50, "jitter": 0.5})")),
            "");
}

TEST(Instances, PlacementIdsFollowFileOrder) {
  const Scene s = load_scene_file(write_small_forest_for_test());
  const PlacementIds ids(s);
  EXPECT_EQ(ids.count, 1 + 12 + 3u);
  EXPECT_EQ(ids.first[0], 0u);
  EXPECT_EQ(ids.first[1], 1u);
  EXPECT_EQ(ids.first[2], 1 + s.objects[1].instances.size());
  for (size_t o = 0; o < 4; ++o)
    for (size_t k = 0; k < std::max<size_t>(1, s.objects[o].instances.size()); ++k)
      EXPECT_EQ(ids.object_of(ids.first[o] + k), o);
  EXPECT_EQ(ids.object_of(ids.count), 4u);
  const Scene copies = scene_as_copies(s);
  ASSERT_EQ(copies.objects.size(), ids.count);
  EXPECT_EQ(copies.objects[1].name, "oak#0");
  EXPECT_EQ(copies.triangle_count(), instanced_triangle_count(s));
  EXPECT_FALSE(has_instances(copies));
  ASSERT_TRUE(copies.objects[1].proxy.has_value());  // each copy keeps its placed proxy
  const glm::vec3 c = copies.objects[1].proxy->shapes[0].center;
  const glm::vec3 expected = place_point(s.objects[1].instances[0], glm::vec3(0, 1.4f, 0));
  EXPECT_NEAR(glm::length(c - expected), 0.0f, 1e-5f);
}

// Must-show 2 (G-buffer half): the instanced forest and its copies give the same G-buffer, bit
// for bit, on every channel. The world-space triangle is formed by the same float operations in
// both, and the barycentrics are recomputed from it (gbuffer.cpp), not taken from Embree, whose
// instance traversal works in the prototype's space.
TEST(Instances, GBufferOfInstancesEqualsCopiesBitForBit) {
  for (const bool terrain : {false, true}) {  // on flat ground, and standing on a terrain
    const Scene s = load_scene_file(
        testutil::write_small_forest(testutil::test_temp_dir("forest-gbuffer"), terrain));
    const Scene copies = scene_as_copies(s);
    const EmbreeScene instanced(s), flat(copies);
    for (const View& v : s.views) {
      const Camera cam = make_camera(v, 0, 0);
      const GBuffer a = render_gbuffer(instanced, cam), b = render_gbuffer(flat, cam);
      EXPECT_TRUE(same_bits(a.coverage, b.coverage)) << v.name;
      EXPECT_TRUE(same_bits(a.depth, b.depth)) << v.name;
      EXPECT_TRUE(same_bits(a.position, b.position)) << v.name;
      EXPECT_TRUE(same_bits(a.normal, b.normal)) << v.name;
      EXPECT_TRUE(same_bits(a.geometric_normal, b.geometric_normal)) << v.name;
      EXPECT_TRUE(same_bits(a.object_id, b.object_id)) << v.name;
      // The test means something: many placements are seen, the mirrored rock among them.
      std::set<float> seen(a.object_id.begin(), a.object_id.end());
      EXPECT_GE(seen.size(), 6u) << v.name;
    }
  }
}

TEST(Instances, BadTransformsAreOneClearLine) {
  EXPECT_NE(load_error(with_instances(R"([{"scale": [1, 1e-9, 1]}])"))
                .find("instances[0]: the "
                      "transform is singular"),
            std::string::npos);
  EXPECT_NE(load_error(with_instances(R"([{"scale": [1, 1, 1]}, {"scale": [0, 1, 1]}])"))
                .find("instances[1]: the transform is singular"),
            std::string::npos);
  EXPECT_NE(
      load_error(with_instances(R"([{"translate": [9.9e6, 0, 0], "scale": [2e5, 2e5, 2e5]}])"))
          .find("instances[0]: the placed copy reaches a coordinate beyond"),
      std::string::npos);
  EXPECT_NE(load_error(with_instances(R"({"placer": "jittered-grid", "count": 100000000})"))
                .find("instances.count"),
            std::string::npos);
  EXPECT_NE(
      load_error(with_instances(R"({"placer": "jittered-grid", "count": 4, "share": [2, 2]})"))
          .find("instances.share"),
      std::string::npos);
  EXPECT_NE(
      load_error(with_instances(R"({"placer": "poisson", "count": 4})")).find("instances.placer"),
      std::string::npos);
  EXPECT_NE(load_error(with_instances(R"({"placer": "jittered-grid", "count": 4, "spacing": 2})"))
                .find("spacing"),
            std::string::npos);
  EXPECT_NE(load_error(with_instances("7")).find("expected an array of transforms or a placer"),
            std::string::npos);
  // A NaN cannot be written in JSON; the check itself refuses one.
  glm::mat4 nan(1.0f);
  nan[1][1] = std::numeric_limits<float>::quiet_NaN();
  Bounds unit;
  unit.extend(glm::vec3(-1.0f));
  unit.extend(glm::vec3(1.0f));
  try {
    validate_instance(nan, unit, "f.json: objects[0].instances[4]");
    FAIL() << "a NaN transform was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "f.json: objects[0].instances[4]: the transform is not finite (NaN or infinite "
                 "entries)");
  }
}

TEST(Instances, MemoryGuardRefusesCopiesThatWouldNotFit) {
  const Scene s = load_scene_file(write_small_forest_for_test());
  const double copies = estimated_bytes(s, true), instanced = estimated_bytes(s, false);
  EXPECT_GT(copies, instanced);
  EXPECT_NO_THROW(check_scene_memory(s, copies, 0, "as copies"));  // unknown: nothing refused
  EXPECT_NO_THROW(check_scene_memory(s, copies, static_cast<size_t>(copies) + 1, "as copies"));
  try {
    check_scene_memory(s, copies, static_cast<size_t>(copies / 2),
                       "the scene written out as copies");
    FAIL() << "not refused";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("scene 'forest': the scene written out as copies (", 0), 0u) << m;
    EXPECT_NE(m.find("GiB of memory"), std::string::npos) << m;
    EXPECT_NE(m.find("available"), std::string::npos) << m;
  }
  // 10^7 placements of a 300k-triangle tree would be 3e12 triangles as copies: far past any
  // machine, while the instanced scene is a few GB.
  EXPECT_GT(3e12 * kBytesPerTriangleBudget, 1e14);
}

TEST(Instances, ConsumersWithoutInstancesRefuseByName) {
  const Scene s = load_scene_file(write_small_forest_for_test());
  try {
    refuse_instances(s, "the Vulkan raster G-buffer");
    FAIL() << "not refused";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 ("scene 'forest': object 'oak' is instanced (" +
                  std::to_string(s.objects[1].instances.size()) +
                  " instances); the Vulkan raster G-buffer reads world-space copies and does not "
                  "take instanced objects")
                     .c_str());
  }
  EXPECT_NO_THROW(refuse_instances(scene_as_copies(s), "x"));
}

// A sequence may name an instanced object: every placement moves with it, and the motion of
// each G-buffer id is its object's.
TEST(Instances, SequenceMovesEveryPlacementOfANamedObject) {
  Scene s = load_scene_file(write_small_forest_for_test());
  View v = s.views[0];
  Sequence seq;
  seq.frames = 2;
  seq.objects["rock"] = {ObjectKey{.frame = 0}, ObjectKey{.frame = 1, .translate = {0, 0.5f, 0}}};
  v.sequence = seq;
  const SequenceFrame f = sequence_frame(s, v, 1);
  const PlacementIds ids(s);
  ASSERT_EQ(f.motion.size(), ids.count);
  EXPECT_TRUE(f.moves_objects);
  for (size_t k = 0; k < 3; ++k) EXPECT_NE(f.motion[ids.first[3] + k], glm::mat4(1.0f));
  EXPECT_EQ(f.motion[ids.first[1]], glm::mat4(1.0f));
  const Scene posed = posed_scene(s, f);
  for (size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(posed.objects[3].instances[k][3].y - s.objects[3].instances[k][3].y, 0.5f, 1e-6f);
  EXPECT_EQ(posed.objects[3].mesh.positions, s.objects[3].mesh.positions);
}

}  // namespace
}  // namespace aoeval
