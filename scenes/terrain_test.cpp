// Terrain (issue 45): the terrain generator against closed forms (a tilted plane gives that plane's
// heights and normals), the height query (scenes/surface_height.h) and objects standing "on" it
// (scenes/stand_on.h): placements and grass blades at the triangle's own height, bad input one
// line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/generators/generators.h"
#include "scenes/scene.h"
#include "scenes/surface_height.h"

namespace aoeval {
namespace {

using nlohmann::json;

GeneratedGeometry terrain(const json& params, uint64_t seed = 1) {
  JsonReader reader(params, "test.json", "objects[0].params");
  GeneratedGeometry g = generate_terrain(seed, reader);
  reader.finish();
  return g;
}

std::string terrain_error(const json& params) {
  try {
    terrain(params);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string load_error(const std::string& text) {
  const std::string path = (testutil::test_temp_dir("terrain") / "bad.json").string();
  std::ofstream(path) << text;
  try {
    load_scene_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Terrain, TiltedPlaneGivesThePlanesHeightsAndNormals) {
  // amplitude 0: y = 0.3 x - 0.2 z exactly (to float rounding), every triangle facing +Y with the
  // plane's normal (-0.3, 1, 0.2) / |.|; between the vertices the query returns the same plane.
  const GeneratedGeometry g =
      terrain({{"size", {20, 10}}, {"resolution", 16}, {"amplitude", 0}, {"slope", {0.3, -0.2}}});
  ASSERT_EQ(g.mesh.triangle_count(), 2u * 16 * 16);
  ASSERT_EQ(g.mesh.vertex_count(), 17u * 17);
  for (const glm::vec3& p : g.mesh.positions)
    EXPECT_NEAR(p.y, 0.3 * p.x - 0.2 * p.z, 1e-5) << p.x << " " << p.z;
  const glm::dvec3 plane = glm::normalize(glm::dvec3(-0.3, 1.0, 0.2));
  for (const auto& t : g.mesh.triangles) {
    const glm::dvec3 a(g.mesh.positions[t.x]), b(g.mesh.positions[t.y]), c(g.mesh.positions[t.z]);
    EXPECT_GT(glm::dot(glm::normalize(glm::cross(b - a, c - a)), plane), 1.0 - 1e-9);
  }
  const SurfaceHeight surface(g.mesh);
  for (int k = 0; k < 200; ++k) {  // a lattice of spots, off the vertices and on them
    const double x = -10.0 + 20.0 * (k % 20) / 19.0, z = -5.0 + 10.0 * (k / 20) / 9.0;
    const auto p = surface.at(x, z);
    ASSERT_TRUE(p) << x << " " << z;
    EXPECT_NEAR(p->y, 0.3 * x - 0.2 * z, 1e-5) << x << " " << z;
    EXPECT_GT(glm::dot(glm::dvec3(p->normal), plane), 1.0 - 1e-6);
  }
  EXPECT_FALSE(surface.at(10.5, 0.0));  // beyond the edge
}

TEST(Terrain, NoiseStaysWithinItsAmplitudeAndRepeatsItsBits) {
  const json params = {{"size", {60, 60}},     {"resolution", 64}, {"amplitude", 3},
                       {"feature_length", 30}, {"octaves", 3},     {"slope", {0.1, 0}}};
  const GeneratedGeometry a = terrain(params, 7), b = terrain(params, 7), c = terrain(params, 8);
  EXPECT_EQ(content_hash(a.mesh), content_hash(b.mesh));
  EXPECT_NE(content_hash(a.mesh), content_hash(c.mesh));
  double lo = 1e9, hi = -1e9;
  for (const glm::vec3& p : a.mesh.positions) {
    const double relief = p.y - 0.1 * p.x;
    EXPECT_LE(std::fabs(relief), 3.0 + 1e-5);
    lo = std::min(lo, relief), hi = std::max(hi, relief);
  }
  EXPECT_GT(hi - lo, 1.5);  // it is not flat: three octaves over four features span most of it
}

// The query kept to a footprint (what a grass field asks for) answers as the whole surface's inside
// it, bit for bit, with fewer triangles; and each triangle of a regular grid is listed only in the
// cells of its own grid cell, so a query over a cell boundary still finds the edge's height.
TEST(Terrain, AFootprintsQueryAnswersAsTheWholeSurfaces) {
  const GeneratedGeometry g = terrain({{"size", {60, 60}},
                                       {"resolution", 64},
                                       {"amplitude", 3},
                                       {"feature_length", 30},
                                       {"octaves", 3}},
                                      5);
  const SurfaceHeight whole(g.mesh);
  const SurfaceHeight::Footprint box{-7.3, 9.1, 2.2, 17.9};
  const SurfaceHeight part(g.mesh, box);
  int compared = 0;
  for (int i = 0; i <= 200; ++i)
    for (int k = 0; k <= 200; ++k) {
      const double x = box.x0 + (box.x1 - box.x0) * i / 200.0;
      const double z = box.z0 + (box.z1 - box.z0) * k / 200.0;
      const auto a = whole.at(x, z), b = part.at(x, z);
      ASSERT_TRUE(a && b) << x << " " << z;
      EXPECT_EQ(a->y, b->y) << x << " " << z;
      ++compared;
    }
  EXPECT_EQ(compared, 201 * 201);
  // Every vertex, on four cells' boundaries, is found, at its own height.
  for (const glm::vec3& p : g.mesh.positions) {
    const auto a = whole.at(p.x, p.z);
    ASSERT_TRUE(a) << p.x << " " << p.z;
    EXPECT_NEAR(a->y, p.y, 1e-5);
  }
}

// A placer's share that gets no spot (one tree over four prototypes, as `bench scale --counts 1`
// asks) leaves its object out: no copy, not one plain copy at the object's own transform, and no
// refusal of its "on".
TEST(Terrain, AShareWithNoSpotLeavesItsObjectOut) {
  const std::string path = (testutil::test_temp_dir("terrain") / "one-tree.json").string();
  std::string objects = R"({"name": "ground", "generator": "terrain", "role": "ground",
      "params": {"size": [40, 40], "resolution": 16, "amplitude": 1, "feature_length": 20}})";
  for (int k = 0; k < 4; ++k)
    objects += R"(, {"name": "t)" + std::to_string(k) +
               R"(", "generator": "sphere", "on": "ground", "instances": {"placer": "jittered-grid",
      "seed": 3, "count": 1, "center": [0, 0, 0], "size": [20, 20], "share": [)" +
               std::to_string(k) + R"(, 4]}})";
  std::ofstream(path)
      << R"({"objects": [)" + objects +
             R"(], "views": [{"name": "v", "eye": [0, 5, 30], "target": [0, 0, 0]}]})";
  const Scene s = load_scene_file(path);
  ASSERT_EQ(s.objects.size(), 2u);  // the terrain and the one share that got the spot
  EXPECT_EQ(s.objects[1].instances.size(), 1u);
}

TEST(Terrain, BadParametersAreOneClearLine) {
  EXPECT_NE(terrain_error({{"resolution", 0}}).find("resolution"), std::string::npos);
  EXPECT_NE(terrain_error({{"amplitude", -1}}).find("amplitude"), std::string::npos);
  EXPECT_NE(terrain_error({{"size", {0, 10}}}).find("size"), std::string::npos);
  // 8 octaves of 40 units: the finest is 0.31, under two cells of 100 / 128.
  const std::string aliased = terrain_error({{"octaves", 8}});
  EXPECT_NE(aliased.find("feature_length: the finest octave"), std::string::npos) << aliased;
  EXPECT_EQ(aliased.find('\n'), std::string::npos);
}

TEST(Terrain, PlacementsAndBladesStandOnTheTriangles) {
  // Trees (placer), rocks (list, y 0 = on the ground) and a meadow on a sloping noise terrain:
  // every placement's origin and every blade's root midpoint is on the surface, to float rounding.
  const std::string path = (testutil::test_temp_dir("terrain") / "meadow.json").string();
  std::ofstream(path) << R"({"objects": [
    {"name": "ground", "generator": "terrain", "seed": 3, "role": "ground",
     "params": {"size": [20, 20], "resolution": 32, "amplitude": 1.5, "feature_length": 10,
                "octaves": 2, "slope": [0.2, 0]}},
    {"name": "meadow", "generator": "grass", "seed": 2, "role": "grass", "on": "ground",
     "params": {"size": [6, 6], "density": 20, "blade_height": 0.3}},
    {"name": "ball", "generator": "sphere", "on": "ground",
     "instances": {"placer": "poisson-disk", "seed": 4, "count": 40, "size": [16, 16]}}],
   "views": [{"name": "v", "eye": [0, 5, 20], "target": [0, 0, 0]}]})";
  const Scene s = load_scene_file(path);
  const SurfaceHeight surface(s.objects[0].mesh);
  const SceneObject& meadow = s.objects[1];
  ASSERT_EQ(meadow.on, "ground");
  const size_t stride = 7, blades = meadow.mesh.vertex_count() / stride;
  ASSERT_EQ(blades, 720u);
  double lifted = 0.0;
  for (size_t b = 0; b < blades; ++b) {
    const glm::vec3* v = &meadow.mesh.positions[b * stride];
    const auto p = surface.at(0.5 * (v[0].x + v[1].x), 0.5 * (v[0].z + v[1].z));
    ASSERT_TRUE(p);
    EXPECT_NEAR(v[0].y, p->y, 1e-5);
    EXPECT_NEAR(v[stride - 1].y - v[0].y, 0.3f, 1e-5);  // eq. 9's h kept exactly
    lifted = std::max(lifted, std::fabs(static_cast<double>(p->y)));
  }
  EXPECT_GT(lifted, 0.5);  // the test means something: the ground is not at y = 0 there
  ASSERT_EQ(s.objects[2].instances.size(), 40u);
  for (const glm::mat4& m : s.objects[2].instances)
    EXPECT_NEAR(m[3].y, surface.at(m[3].x, m[3].z)->y, 1e-5);
}

TEST(Terrain, BadOnIsOneClearLine) {
  const std::string view =
      R"(], "views": [{"name": "v", "eye": [0, 5, 20], "target": [0, 0, 0]}]})";
  const std::string ground =
      R"({"objects": [{"name": "ground", "generator": "plane", "params": {"size": [4, 4]}},)";
  const std::string missing = load_error(
      ground + R"({"name": "b", "generator": "sphere", "on": "hill", "instances": [{}]})" + view);
  EXPECT_NE(missing.find("object 'b', on 'hill': no object of that name"), std::string::npos)
      << missing;
  const std::string outside = load_error(
      ground +
      R"({"name": "b", "generator": "sphere", "on": "ground", "instances": [{"translate": [9, 0, 0]}]})" +
      view);
  EXPECT_NE(outside.find("instances[0]: the spot (x 9, z 0) lies outside object 'ground'"),
            std::string::npos)
      << outside;
  const std::string plain =
      load_error(ground + R"({"name": "b", "generator": "sphere", "on": "ground"})" + view);
  EXPECT_NE(plain.find("objects[1].on: only instanced objects and grass fields"), std::string::npos)
      << plain;
  for (const auto& e : {missing, outside, plain}) EXPECT_EQ(e.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace aoeval
