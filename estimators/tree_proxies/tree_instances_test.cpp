// Tree envelopes of an instanced forest (issue 45): one per placement, in G-buffer id order, equal
// to the envelopes of the same forest written as copies where the scene gives the proxy, and
// enclosing every placed leaf where it is derived; the row records an instanced object's proxy
// once, in object space, and that record placed by an instance's transform is that tree's envelope.
#include <gtest/gtest.h>

#include <cmath>

#include "base/testing/test_temp_dir.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "estimators/tree_proxies/tree_scene.h"
#include "scenes/instances.h"
#include "scenes/surface_height.h"
#include "scenes/testing_forest.h"

namespace aoeval {
namespace {

Scene forest() {
  return load_scene_file(testutil::write_small_forest(testutil::test_temp_dir("forest")));
}

TEST(TreeInstances, EnvelopesPerPlacementMatchCopies) {
  const Scene s = forest();
  const Scene copies = scene_as_copies(s);
  ProxyOptions sphere;
  const auto inst = tree_envelopes(s, sphere, true);
  const auto flat = tree_envelopes(copies, sphere, true);
  const PlacementIds ids(s);
  ASSERT_EQ(inst.size(), 12u);
  ASSERT_EQ(flat.size(), 12u);
  for (size_t t = 0; t < inst.size(); ++t) {
    EXPECT_EQ(inst[t].placement, flat[t].placement);
    EXPECT_EQ(ids.object_of(inst[t].placement), inst[t].object);
    const Ellipsoid &a = inst[t].proxy.shapes[0], &b = flat[t].proxy.shapes[0];
    if (inst[t].object == 1) {  // oak: the scene's proxy and density, placed alike
      EXPECT_TRUE(inst[t].from_scene);
      EXPECT_LE(glm::length(a.center - b.center), 1e-5f);
      EXPECT_NEAR(a.radii.x, b.radii.x, 1e-5f);
      EXPECT_NEAR(inst[t].lambda[0] / flat[t].lambda[0], 1.0, 1e-4);
    } else {  // birch: derived from the prototype, placed; it still holds every placed leaf
      const SceneObject& c = copies.objects[inst[t].placement];
      const LeafSet leaves = tree_leaves(c);
      for (size_t tri = leaves.first_triangle; tri < c.mesh.triangle_count(); ++tri)
        for (int k = 0; k < 3; ++k)
          EXPECT_LE(glm::length(c.mesh.positions[c.mesh.triangles[tri][k]] - a.center),
                    a.radii.x * (1.0f + 1e-5f));
      // Both spheres hold every leaf but are centred on different boxes (the prototype's box,
      // placed, against the placed leaves' box), so their radii agree only roughly.
      EXPECT_GE(a.radii.x, b.radii.x * 0.9f);
      EXPECT_LE(a.radii.x, b.radii.x * 1.5f);
    }
  }
}

TEST(TreeInstances, ProxiesRiseWithTheTerrainTheTreesStandOn) {
  // The same forest on flat ground and standing "on" a sloping noise terrain: every tree's
  // envelope (the scene's sphere for the oaks, derived for the birches) moves up by the terrain's
  // height under its placement, and not sideways.
  const Scene flat = forest();
  const Scene raised = load_scene_file(
      testutil::write_small_forest(testutil::test_temp_dir("forest-terrain"), true));
  const SurfaceHeight ground(raised.objects[0].mesh);
  for (ProxyKind kind : {ProxyKind::sphere, ProxyKind::ellipsoid, ProxyKind::shells}) {
    ProxyOptions options;
    options.kind = kind;
    const auto a = tree_envelopes(flat, options, true), b = tree_envelopes(raised, options, true);
    ASSERT_EQ(a.size(), 12u);
    ASSERT_EQ(b.size(), 12u);
    const PlacementIds ids(raised);
    double highest = 0.0;
    for (size_t t = 0; t < a.size(); ++t) {
      const SceneObject& o = raised.objects[b[t].object];
      const glm::mat4& m = o.instances[b[t].placement - ids.first[b[t].object]];
      const float h = ground.at(m[3].x, m[3].z)->y;
      highest = std::max(highest, std::fabs(static_cast<double>(h)));
      ASSERT_EQ(a[t].proxy.shapes.size(), b[t].proxy.shapes.size());
      for (size_t k = 0; k < a[t].proxy.shapes.size(); ++k) {
        const glm::vec3 d = b[t].proxy.shapes[k].center - a[t].proxy.shapes[k].center;
        EXPECT_NEAR(d.x, 0.0f, 1e-5f);
        EXPECT_NEAR(d.y, h, 1e-5f) << "tree " << t;
        EXPECT_NEAR(d.z, 0.0f, 1e-5f);
      }
    }
    EXPECT_GT(highest, 0.3);  // the terrain lifts some trees well off y = 0
  }
}

TEST(TreeInstances, SceneRulesFollowPlacementIds) {
  const Scene s = forest();
  TreeScene scene;
  ProxyOptions proxy;
  const TreeSceneOptions options{.proxy = proxy,
                                 .prefer_scene = true,
                                 .horizon = true,
                                 .grass_ground = false,
                                 .blade_height = 0.0};
  const auto& envelopes = scene.prepare(s, options);
  const PlacementIds ids(s);
  for (size_t t = 0; t < envelopes.size(); ++t) {
    int called = -1;
    const glm::vec3 x = envelopes[t].proxy.shapes[0].center;
    scene.shade(x, glm::vec3(0, 1, 0), static_cast<float>(envelopes[t].placement),
                [&](size_t tree, const glm::vec3&, const glm::vec3&) {
                  called = static_cast<int>(tree);
                  return 1.0f;
                });
    EXPECT_EQ(called, static_cast<int>(t));
  }
  // A rock (solid) pixel is shaded by the trees only: below 1 near the forest, no self term.
  bool self = false;
  const float v =
      scene.shade(glm::vec3(0, 0.1f, 0), glm::vec3(0, 1, 0), static_cast<float>(ids.first[3] + 1),
                  [&](size_t, const glm::vec3&, const glm::vec3&) {
                    self = true;
                    return 1.0f;
                  });
  EXPECT_FALSE(self);
  EXPECT_LT(v, 1.0f);
}

TEST(TreeInstances, TheRowRecordsAnInstancedObjectsProxyOnceAndPlacingItGivesEachTree) {
  const Scene s = forest();
  TreeScene scene;
  const TreeSceneOptions options{.proxy = ProxyOptions{},
                                 .prefer_scene = true,
                                 .horizon = true,
                                 .grass_ground = false,
                                 .blade_height = 0.0};
  const auto& envelopes = scene.prepare(s, options);
  const nlohmann::json& proxies = scene.derived()["proxies"];
  ASSERT_EQ(proxies.size(), 2u);  // oak and birch, 6 placed trees each
  const PlacementIds ids(s);
  for (const nlohmann::json& p : proxies) {
    EXPECT_EQ(p["instances"], 6);
    EXPECT_EQ(p["space"], "object");
    const size_t object = p["object"] == "oak" ? 1 : 2;
    ASSERT_EQ(s.objects[object].name, p["object"]);
    TreeProxy recorded;
    recorded.type = p["type"];
    for (const nlohmann::json& shape : p["shapes"]) {
      Ellipsoid e;
      e.center = glm::vec3(shape["center"][0], shape["center"][1], shape["center"][2]);
      e.radii = glm::vec3(shape["radii"][0], shape["radii"][1], shape["radii"][2]);
      recorded.shapes.push_back(e);
    }
    for (const TreeEnvelope& e : envelopes) {
      if (e.object != object) continue;
      TreeProxy placed = recorded;
      place_proxy(s.objects[object].instances[e.placement - ids.first[object]], placed);
      EXPECT_LE(glm::length(placed.shapes[0].center - e.proxy.shapes[0].center), 1e-5f);
      EXPECT_NEAR(placed.shapes[0].radii.x, e.proxy.shapes[0].radii.x, 1e-5f);
    }
  }
}

}  // namespace
}  // namespace aoeval
