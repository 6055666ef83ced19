// Reeves-Blau (as Hegeman et al. 2006 describe it): V = exp(-k depth) on tree pixels, 1 elsewhere.
// The estimator is a closed form, so tolerances are float rounding (1e-6).
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "estimators/registry.h"
#include "estimators/tree_proxies/tree_proxy.h"

namespace aoeval {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A tree object: a few leaf triangles inside the unit ball around `c`, with a given proxy.
SceneObject tree(glm::vec3 c, const std::string& type, glm::vec3 radii) {
  SceneObject o;
  o.name = "tree";
  o.role = Role::tree;
  o.mesh.positions = {c + glm::vec3(0.1f, 0, 0), c + glm::vec3(0, 0.1f, 0),
                      c + glm::vec3(0, 0, 0.1f), c - glm::vec3(0.1f, 0, 0)};
  o.mesh.triangles = {{0, 1, 2}, {1, 2, 3}};
  TreeProxy p;
  p.type = type;
  Ellipsoid e;
  e.center = c;
  e.radii = radii;
  p.shapes.push_back(e);
  o.proxy = p;
  return o;
}

GBuffer probes(const std::vector<glm::vec3>& p, const std::vector<float>& id) {
  GBuffer g;
  g.width = static_cast<int>(p.size());
  g.height = 1;
  g.coverage.assign(p.size(), 1.0f);
  g.depth.assign(p.size(), 1.0f);
  g.position = p;
  g.normal.assign(p.size(), glm::vec3(0, 1, 0));
  g.geometric_normal = g.normal;
  g.object_id = id;
  return g;
}

std::vector<float> run(const Scene& scene, const GBuffer& g, nlohmann::json overrides) {
  const EstimatorInfo& info = find_estimator("reeves-blau");
  EmbreeScene es(scene);
  const EstimateContext context{scene, es, g};
  auto e = info.create(resolve_params(info.name, info.params, overrides, "test"));
  e->prepare(context);
  return e->run(context).ao;
}

TEST(ReevesBlau, ExponentialInTheDepthBelowASphere) {
  const glm::vec3 c(1.0f, 3.0f, -2.0f);
  Scene scene;
  scene.objects.push_back(tree(c, "sphere", glm::vec3(2.0f)));
  const float k = 0.7f;
  const GBuffer g =
      probes({c, c + glm::vec3(0, 1.5f, 0), c + glm::vec3(0, 0, -2.0f), c + glm::vec3(3.0f, 0, 0)},
             {0, 0, 0, 0});
  const auto ao = run(scene, g, {{"attenuation", k}});
  EXPECT_NEAR(ao[0], std::exp(-k * 2.0), 1e-6);  // depth R at the centre
  EXPECT_NEAR(ao[1], std::exp(-k * 0.5), 1e-6);  // R - |x - c|
  EXPECT_NEAR(ao[2], 1.0, 1e-6);                 // on the envelope
  EXPECT_EQ(ao[3], 1.0f);                        // outside
}

TEST(ReevesBlau, EllipsoidEnvelopeAndDerivedAttenuation) {
  const glm::vec3 c(0.0f, 5.0f, 0.0f);
  Scene scene;
  scene.objects.push_back(tree(c, "ellipsoid", glm::vec3(1.0f, 4.0f, 1.0f)));
  const GBuffer g = probes({c + glm::vec3(0, 3.0f, 0), c + glm::vec3(0.5f, 0, 0)}, {0, 0});
  // k = lambda = G * leaf area / envelope volume (Hegeman et al. §3).
  const double lambda =
      kLeafProjection * tree_leaves(scene.objects[0]).area / (4.0 / 3.0 * kPi * 4.0);
  const auto ao = run(scene, g, {{"envelope", "ellipsoid"}});
  EXPECT_NEAR(ao[0], std::exp(-lambda * 1.0), 1e-6);  // radial depth 4 - 3
  EXPECT_NEAR(ao[1], std::exp(-lambda * 0.5), 1e-6);  // 1 - 0.5
  // The sphere envelope cannot use the scene's ellipsoid: it derives the leaves' bounding sphere
  // (radius 0.1 around c), so both probes are outside it.
  for (float v : run(scene, g, {{"envelope", "sphere"}})) EXPECT_EQ(v, 1.0f);
}

TEST(ReevesBlau, NonTreePixelsAreOpen) {
  Scene scene;
  scene.objects.push_back(tree(glm::vec3(0.0f), "sphere", glm::vec3(1.0f)));
  SceneObject wall;
  wall.name = "wall";
  wall.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  wall.mesh.triangles = {{0, 1, 2}};
  scene.objects.push_back(wall);
  const auto ao = run(scene, probes({glm::vec3(0.0f), glm::vec3(0.0f)}, {1, -1}), {});
  EXPECT_EQ(ao[0], 1.0f);  // inside the envelope, but not a tree pixel
  EXPECT_EQ(ao[1], 1.0f);
}

}  // namespace
}  // namespace aoeval
