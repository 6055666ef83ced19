// Hegeman et al. 2006 closed forms (eq. 4-9), the ellipsoid mapping, the derived proxies and
// alpha rho, and the tree estimators on small synthetic scenes. The model is deterministic, so the
// tolerances are float rounding: a few ulps of the quantities involved (1e-6 relative), or the
// truncation error of a series where a test checks a limit (stated at the test).
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "estimators/registry.h"
#include "estimators/tree_proxies/hegeman_model.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "references/reference.h"
#include "scenes/corpus.h"
#include "scenes/generators/generators.h"
#include "scenes/random.h"

namespace aoeval {
namespace {

namespace hm = hegeman;
constexpr double kPi = 3.14159265358979323846;

Ellipsoid ellipsoid(glm::vec3 c, glm::vec3 r, glm::mat3 axes = glm::mat3(1.0f)) {
  Ellipsoid e;
  e.center = c;
  e.radii = r;
  e.axes = axes;
  return e;
}

// A rotation about a unit axis by `angle` radians (Rodrigues), columns = rotated basis.
glm::mat3 rotation(glm::vec3 axis, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  const glm::mat3 k(0.0f, axis.z, -axis.y, -axis.z, 0.0f, axis.x, axis.y, -axis.x, 0.0f);
  return glm::mat3(1.0f) + s * k + (1.0f - c) * (k * k);
}

glm::vec3 unit(SplitMix64& rng) {
  for (;;) {
    const glm::vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const float d = glm::dot(p, p);
    if (d > 1e-3f && d <= 1.0f) return p / std::sqrt(d);
  }
}

// ---- eq. 4-6
// --------------------------------------------------------------------------------------

TEST(HegemanModel, CapVolumeOfFullSphereAndHemisphere) {
  for (float R : {0.5f, 1.0f, 3.0f}) {
    const double r3 = double(R) * R * R;
    EXPECT_NEAR(hm::cap_volume(2.0f * R, R), 4.0 / 3.0 * kPi * r3, 1e-6 * r3);  // eq. 4, h = 2R
    EXPECT_NEAR(hm::cap_volume(R, R), 2.0 / 3.0 * kPi * r3, 1e-6 * r3);         // h = R
    EXPECT_EQ(hm::cap_volume(0.0f, R), 0.0f);
  }
}

TEST(HegemanModel, CapGeometryAndOffCentreFactor) {
  const glm::vec3 c(1.0f, 2.0f, 3.0f);
  const float R = 2.0f;
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  // At the centre: a hemisphere, on the disk's centre, f = 1 (eq. 5 with d = 0).
  hm::Cap k = hm::cap_geometry(c, n, c, R);
  EXPECT_FLOAT_EQ(k.h, R);
  EXPECT_EQ(k.d2, 0.0f);
  EXPECT_EQ(hm::off_center_factor(k.h * k.h, k.d2), 1.0f);
  // Off centre in the central plane by a: h = R, d = a, f = R^2 / (R^2 + a^2).
  k = hm::cap_geometry(c + glm::vec3(1.5f, 0.0f, 0.0f), n, c, R);
  EXPECT_FLOAT_EQ(k.h, R);
  EXPECT_FLOAT_EQ(k.d2, 2.25f);
  EXPECT_FLOAT_EQ(hm::off_center_factor(k.h * k.h, k.d2), 4.0f / 6.25f);
  // On the boundary facing out: empty cap, V = 1; facing in: the whole sphere.
  EXPECT_EQ(hm::sphere_visibility(c + R * n, n, c, R, 5.0f), 1.0f);
  k = hm::cap_geometry(c + R * n, -n, c, R);
  EXPECT_FLOAT_EQ(k.h, 2.0f * R);
  const float alpha_rho = 0.1f;
  EXPECT_NEAR(hm::sphere_visibility(c + R * n, -n, c, R, alpha_rho),
              std::exp(-alpha_rho * 4.0 / 3.0 * kPi * 8.0), 1e-6);
  // Far in front of the sphere, facing away: nothing in the cap.
  EXPECT_EQ(hm::sphere_visibility(c + 5.0f * n, n, c, R, 5.0f), 1.0f);
}

TEST(HegemanModel, EllipsoidWithEqualRadiiIsTheSphere) {
  SplitMix64 rng(42);
  for (int trial = 0; trial < 2000; ++trial) {
    const float R = rng.uniform(0.3f, 3.0f);
    const glm::vec3 c(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    const glm::mat3 axes = rotation(unit(rng), rng.uniform(0.0f, 6.2f));
    const hm::UnitMap m = hm::make_unit_map(ellipsoid(c, glm::vec3(R), axes));
    const glm::vec3 x = c + rng.uniform(0.0f, 1.5f * R) * unit(rng), n = unit(rng);
    const float alpha_rho = rng.uniform(0.01f, 2.0f) / (R * R * R);
    EXPECT_NEAR(hm::ellipsoid_visibility(x, n, m, alpha_rho),
                hm::sphere_visibility(x, n, c, R, alpha_rho), 1e-6);
    EXPECT_NEAR(
        hm::large_occluder_visibility(x, n, m, true),
        hm::large_occluder_visibility(x, n, hm::make_unit_map(ellipsoid(c, glm::vec3(R))), true),
        1e-6);
  }
}

TEST(HegemanModel, EllipsoidCentreCutsHalfItsVolume) {
  // Any plane through the centre halves an ellipsoid: V = exp(-alpha rho 2/3 pi a b c) for every n.
  const hm::UnitMap m =
      hm::make_unit_map(ellipsoid(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f, 3.0f, 0.5f),
                                  rotation(glm::vec3(0.0f, 0.6f, 0.8f), 0.7f)));
  SplitMix64 rng(5);
  for (int i = 0; i < 100; ++i)
    EXPECT_NEAR(hm::ellipsoid_visibility(glm::vec3(0.0f, 1.0f, 0.0f), unit(rng), m, 0.2f),
                std::exp(-0.2 * 2.0 / 3.0 * kPi * 1.5), 1e-6);
  // At the top of an axis-aligned ellipsoid facing down the whole ellipsoid is in the cap.
  const hm::UnitMap a = hm::make_unit_map(ellipsoid(glm::vec3(0.0f), glm::vec3(1.0f, 3.0f, 0.5f)));
  EXPECT_NEAR(
      hm::ellipsoid_visibility(glm::vec3(0.0f, 3.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f), a, 0.2f),
      std::exp(-0.2 * 4.0 / 3.0 * kPi * 1.5), 1e-6);
}

// ---- eq. 7-8
// --------------------------------------------------------------------------------------

TEST(HegemanModel, LargeOccluderTendsToTheSolidAngleOfASmallSphere) {
  const float r = 1.0f;
  const hm::UnitMap m = hm::make_unit_map(ellipsoid(glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(r)));
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  for (double d : {10.0, 30.0, 100.0}) {
    const glm::vec3 x(0.0f, -static_cast<float>(d), 0.0f);  // the sphere straight overhead
    const double occlusion = 1.0 - hm::large_occluder_visibility(x, up, m, true);
    // The exact solid angle of a sphere, 2 pi (1 - sqrt(1 - r^2/d^2)) = pi r^2/d^2 (1 + r^2/(4 d^2)
    // + ...): eq. 8's 1 - V = r^2 / (2 d^2) matches it to relative r^2 / (4 d^2), plus float
    // rounding of 1 - V (1 ulp of 1 = 6e-8 absolute).
    const double exact = (1.0 - std::sqrt(1.0 - r * r / (d * d)));
    EXPECT_NEAR(occlusion / exact, 1.0, r * r / (4.0 * d * d) + 6e-8 / exact + 1e-6) << d;
    EXPECT_NEAR(occlusion, r * r / (2.0 * d * d), 6e-8) << d;
  }
  // And no occlusion as d -> infinity (1 - V = 5e-9 rounds to 1 in float).
  EXPECT_EQ(hm::large_occluder_visibility(glm::vec3(0.0f, -1e4f, 0.0f), up, m, true), 1.0f);
  // Horizon: a sphere wholly below the tangent plane does not occlude; centred on it, half counts.
  EXPECT_EQ(hm::large_occluder_visibility(glm::vec3(0.0f, 3.0f, 0.0f), up, m, true), 1.0f);
  EXPECT_NEAR(hm::large_occluder_visibility(glm::vec3(0.0f, 3.0f, 0.0f), up, m, false),
              1.0 - 1.0 / 18.0, 1e-6);
  EXPECT_NEAR(1.0 - hm::large_occluder_visibility(glm::vec3(4.0f, 0.0f, 0.0f), up, m, true),
              0.5 / 32.0, 1e-6);
  EXPECT_NEAR(hm::above_horizon_fraction(0.0f), 0.5, 1e-6);
  // Inside the sphere eq. 7 exceeds 2 pi: clamped to 0.
  EXPECT_EQ(hm::large_occluder_visibility(glm::vec3(0.0f, -0.5f, 0.0f), up, m, false), 0.0f);
}

TEST(HegemanModel, EllipsoidSilhouetteArea) {
  // Axis-aligned (a, b, c) seen from far along z: silhouette pi a b; along x: pi b c.
  const hm::UnitMap m = hm::make_unit_map(ellipsoid(glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 3.0f)));
  const float d = 50.0f;
  EXPECT_NEAR(1.0 - hm::large_occluder_visibility(glm::vec3(0, 0, -d), glm::vec3(0, 0, 1), m, true),
              kPi * 2.0 / (d * d) / (2.0 * kPi), 1e-6);
  EXPECT_NEAR(1.0 - hm::large_occluder_visibility(glm::vec3(-d, 0, 0), glm::vec3(1, 0, 0), m, true),
              kPi * 6.0 / (d * d) / (2.0 * kPi), 1e-6);
}

// ---- eq. 9
// ----------------------------------------------------------------------------------------

TEST(HegemanModel, GrassTipIsOpenRootIsClosed) {
  const float h = 0.3f;
  EXPECT_EQ(hm::grass_visibility(h, h, 1.0f), 1.0f);  // tip, normal up
  EXPECT_EQ(hm::grass_visibility(h, h, 0.0f), 0.5f);  // tip, normal horizontal
  for (float c : {-1.0f, 0.0f, 1.0f}) EXPECT_EQ(hm::grass_visibility(0.0f, h, c), 0.0f);  // root
  EXPECT_FLOAT_EQ(hm::grass_visibility(0.15f, h, 1.0f), 0.5f);  // linear in P_z
  EXPECT_EQ(hm::grass_visibility(2.0f * h, h, 1.0f), 1.0f);     // above the tips: clamped
}

// ---- Reeves-Blau depth
// ------------------------------------------------------------------------------

TEST(HegemanModel, EnvelopeDepth) {
  const glm::vec3 c(0.0f, 2.0f, 0.0f);
  const hm::UnitMap s = hm::make_unit_map(ellipsoid(c, glm::vec3(1.5f)));
  EXPECT_FLOAT_EQ(hm::envelope_depth(c, s), 1.5f);
  EXPECT_NEAR(hm::envelope_depth(c + glm::vec3(0.6f, 0.0f, 0.8f), s), 0.5, 1e-6);
  EXPECT_NEAR(hm::envelope_depth(c + glm::vec3(0.0f, -1.5f, 0.0f), s), 0.0, 1e-6);
  EXPECT_EQ(hm::envelope_depth(c + glm::vec3(3.0f, 0.0f, 0.0f), s), 0.0f);
  const hm::UnitMap e = hm::make_unit_map(ellipsoid(c, glm::vec3(1.0f, 3.0f, 0.5f)));
  EXPECT_NEAR(hm::envelope_depth(c + glm::vec3(0.0f, 2.0f, 0.0f), e), 1.0, 1e-6);
  EXPECT_NEAR(hm::envelope_depth(c + glm::vec3(0.2f, 0.0f, 0.0f), e), 0.8, 1e-6);
  EXPECT_FLOAT_EQ(hm::envelope_depth(c, e), 0.5f);
}

// ---- proxies
// ----------------------------------------------------------------------------------------

TEST(TreeProxy, KMeansIsDeterministicAndFindsSeparatedBlobs) {
  std::vector<glm::dvec3> pts;
  std::vector<double> w;
  SplitMix64 rng(3);
  for (int i = 0; i < 500; ++i) {
    const glm::dvec3 blob = i % 2 ? glm::dvec3(10, 0, 0) : glm::dvec3(-10, 0, 0);
    pts.push_back(blob + glm::dvec3(unit(rng)));
    w.push_back(1.0 + (i % 3));
  }
  const KMeans a = kmeans(pts, w, 2, 9), b = kmeans(pts, w, 2, 9);
  ASSERT_EQ(a.centers.size(), 2u);
  EXPECT_EQ(a.assignment, b.assignment);
  for (int c = 0; c < 2; ++c)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.centers[c][k], b.centers[c][k]);
  // Each centre is its blob's weighted mean.
  for (int c = 0; c < 2; ++c) {
    glm::dvec3 sum(0.0);
    double wsum = 0.0;
    for (size_t i = 0; i < pts.size(); ++i)
      if (a.assignment[i] == c) {
        sum += w[i] * pts[i];
        wsum += w[i];
      }
    EXPECT_NEAR(glm::length(sum / wsum - a.centers[c]), 0.0, 1e-12);
    EXPECT_NEAR(std::fabs(a.centers[c].x), 10.0, 0.2);
  }
}

bool inside(const Ellipsoid& e, glm::vec3 p) {
  const glm::vec3 q = glm::transpose(e.axes) * (p - e.center) / e.radii;
  return glm::dot(q, q) <= 1.0f + 1e-6f;
}

class CorpusTree : public ::testing::TestWithParam<const char*> {};

TEST_P(CorpusTree, DerivedProxiesCoverEveryLeafAndAreDeterministic) {
  const Scene scene = load_scene(GetParam());
  const SceneObject& o = scene.objects.back();
  ASSERT_EQ(o.role, Role::tree);
  const LeafSet leaves = tree_leaves(o);
  EXPECT_NEAR(leaves.area, o.facts["leaf_area"].get<double>(), 1e-6 * leaves.area);
  for (ProxyKind kind : {ProxyKind::sphere, ProxyKind::ellipsoid, ProxyKind::shells}) {
    ProxyOptions opt;
    opt.kind = kind;
    const TreeProxy p = derive_proxy(o, opt), q = derive_proxy(o, opt);
    ASSERT_EQ(p.shapes.size(), kind == ProxyKind::shells ? 4u : 1u);
    for (size_t s = 0; s < p.shapes.size(); ++s) {
      EXPECT_EQ(p.shapes[s].center, q.shapes[s].center);
      EXPECT_EQ(p.shapes[s].radii, q.shapes[s].radii);
    }
    size_t outside = 0;
    for (size_t t = leaves.first_triangle; t < o.mesh.triangle_count(); ++t)
      for (int c = 0; c < 3; ++c) {
        const glm::vec3 v = o.mesh.positions[o.mesh.triangles[t][c]];
        bool in = false;
        for (const auto& e : p.shapes) in = in || inside(e, v);
        outside += !in;
      }
    EXPECT_EQ(outside, 0u) << proxy_kind_name(kind);
  }
  // The derived sphere is the generator's bounding sphere (untransformed corpus trees).
  ProxyOptions opt;
  const Ellipsoid s = derive_proxy(o, opt).shapes.front();
  const auto& bs = o.facts["bounding_sphere"];
  EXPECT_NEAR(s.radii.x, bs["radius"].get<double>(), 1e-5);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.center[k], bs["center"][k].get<double>(), 1e-5);
}

INSTANTIATE_TEST_SUITE_P(Trees, CorpusTree, ::testing::Values("tree-apple", "tree-poplar"));

// Eq. 9's h comes from the grass object's world-space height, which for the grass generator is
// exactly its facts.blade_height (the generator puts roots at y = 0 and tips at y = blade_height
// exactly).
TEST(TreeProxy, GrassHeightIsTheGeneratorsBladeHeight) {
  const Scene scene = load_scene("grass-field");
  for (const SceneObject& o : scene.objects)
    if (o.role == Role::grass) {
      const Bounds b = o.mesh.bounds();
      EXPECT_EQ(b.lower.y, 0.0f);
      EXPECT_EQ(b.extent().y, static_cast<float>(o.facts["blade_height"].get<double>()));
    }
}

TEST(TreeProxy, TreeWithoutLeavesIsAnInputError) {
  SceneObject o;
  o.name = "stump";
  o.role = Role::tree;
  o.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  o.mesh.triangles = {{0, 1, 2}};
  o.facts["wood_triangles"] = 1;
  EXPECT_THROW(tree_leaves(o), InputError);
  o.facts["wood_triangles"] = 0;
  EXPECT_NO_THROW(tree_leaves(o));
}

// ---- estimators on synthetic scenes -------------------------------------------------------------

SceneObject sphere_cloud(int count, float radius, uint64_t seed) {
  nlohmann::json params = {{"count", count}, {"radius", radius}, {"triangle_size", 0.05}};
  JsonReader reader(params, "test");
  const GeneratedGeometry g = find_generator("sphere-uniform")->function(seed, reader);
  reader.finish();
  SceneObject o;
  o.name = "ball";
  o.role = Role::tree;
  o.mesh = g.mesh;
  o.facts = g.facts;
  return o;
}

GBuffer probes(const std::vector<glm::vec3>& p, const std::vector<glm::vec3>& n,
               const std::vector<float>& id) {
  GBuffer g;
  g.width = static_cast<int>(p.size());
  g.height = 1;
  g.coverage.assign(p.size(), 1.0f);
  g.depth.assign(p.size(), 1.0f);
  g.position = p;
  g.normal = n;
  g.geometric_normal = n;
  g.object_id = id;
  return g;
}

std::vector<float> estimate(const std::string& name, const Scene& scene, const GBuffer& g,
                            nlohmann::json overrides = nlohmann::json::object()) {
  const EstimatorInfo& info = find_estimator(name);
  EmbreeScene es(scene);
  const EstimateContext context{scene, es, g};
  auto e = info.create(resolve_params(info.name, info.params, overrides, "test"));
  e->prepare(context);
  return e->run(context).ao;
}

TEST(TreeEstimators, DerivedAlphaRhoIsExactAtTheCentre) {
  // At the centre of the envelope every direction travels R inside it: the Poisson model gives
  // exp(-lambda R) with lambda = G A_leaf / V (§3), and the derived alpha rho reproduces it.
  Scene scene;
  scene.objects.push_back(sphere_cloud(2000, 1.0f, 4));
  TreeProxy given;
  given.type = "sphere";
  given.shapes.push_back(ellipsoid(glm::vec3(0.0f), glm::vec3(1.2f)));
  scene.objects[0].proxy = given;
  const double area = tree_leaves(scene.objects[0]).area;
  const double lambda = 0.5 * area / (4.0 / 3.0 * kPi * 1.2 * 1.2 * 1.2);
  const GBuffer g = probes({glm::vec3(0.0f), glm::vec3(0.0f)},
                           {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, 2, 3))}, {0.0f, 0.0f});
  for (const char* name : {"tree-sphere", "tree-ellipsoid"}) {  // (shells derive their own)
    const auto ao = estimate(name, scene, g);
    for (float v : ao) EXPECT_NEAR(v, std::exp(-lambda * 1.2), 1e-6) << name;
  }
  // With the scene's density rho, lambda = G rho (A_leaf / N_leaf).
  scene.objects[0].density = 1000.0;
  const double lambda_rho = 0.5 * 1000.0 * area / 2000.0;
  EXPECT_NEAR(estimate("tree-sphere", scene, g)[0], std::exp(-lambda_rho * 1.2), 1e-6);
  // An explicit alpha_rho is eq. 6 verbatim.
  EXPECT_NEAR(estimate("tree-sphere", scene, g, {{"alpha_rho", 0.3}})[0],
              std::exp(-0.3 * 2.0 / 3.0 * kPi * 1.2 * 1.2 * 1.2), 1e-6);
  // Reeves-Blau with k = lambda agrees at the centre, and gives 1 on the envelope.
  const GBuffer rim = probes({glm::vec3(0.0f), glm::vec3(0.0f, 1.2f, 0.0f)},
                             {glm::vec3(0, 1, 0), glm::vec3(0, 1, 0)}, {0.0f, 0.0f});
  const auto rb = estimate("reeves-blau", scene, rim);
  EXPECT_NEAR(rb[0], std::exp(-lambda_rho * 1.2), 1e-6);
  EXPECT_NEAR(rb[1], 1.0, 1e-6);  // |u| = 1 up to rounding
}

// §3's Poisson argument on real geometry: in sphere-uniform (leaves uniform in the unit ball,
// randomly oriented), the fraction of all directions from the centre that escape, averaged over
// realisations, is exp(-lambda R) with lambda = G A_leaf / V, G = 1/2; which is exactly what the
// derived alpha rho gives at the centre (DerivedAlphaRhoIsExactAtTheCentre). Eight generator seeds;
// per seed the Embree reference at 48 probes at the centre (normals +-x, +-y, +-z, so the
// hemispheres cover the sphere evenly) with 512 rays each. The tolerance is 4 standard errors of
// the mean over seeds, from their spread (which holds the realisation and the ray-sampling noise).
// A wrong G (1 or 1/4) would move the expectation from 0.076 to 0.006 or 0.27. Small leaves (0.02)
// keep the edge effects of the ball's boundary and of leaves straddling the centre (relative size /
// R) far below that tolerance.
TEST(TreeEstimators, PoissonArgumentHoldsAtTheCentreOfSphereUniform) {
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<glm::vec3> p(48, glm::vec3(0.0f)), n;
  for (int k = 0; k < 48; ++k) n.push_back(axes[k % 6]);
  const GBuffer g = probes(p, n, std::vector<float>(48, 0.0f));
  double sum = 0.0, sum_sq = 0.0, expected = 0.0;
  const int seeds = 8;
  for (int seed = 1; seed <= seeds; ++seed) {
    nlohmann::json params = {{"count", 120000}, {"radius", 1.0}, {"triangle_size", 0.02}};
    JsonReader reader(params, "test");
    Scene scene;
    SceneObject o;
    o.name = "ball";
    o.role = Role::tree;
    o.mesh = find_generator("sphere-uniform")->function(static_cast<uint64_t>(seed), reader).mesh;
    scene.objects.push_back(o);
    const double lambda = kLeafProjection * tree_leaves(o).area / (4.0 / 3.0 * kPi);
    expected += std::exp(-lambda) / seeds;
    EmbreeScene es(scene);
    ReferenceSettings rs;
    rs.sampler = SamplerKind::random;
    rs.spp = 512;
    rs.definition.weighting = Weighting::uniform;
    rs.seed = static_cast<uint64_t>(seed);
    const ReferenceImage r = compute_reference(es, g, rs);
    double v = 0.0;
    for (float a : r.ao) v += a / 48.0;
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / seeds;
  const double se = std::sqrt(std::max(0.0, (sum_sq - sum * mean) / (seeds - 1.0)) / seeds);
  EXPECT_NEAR(mean, expected, 4.0 * se) << "standard error " << se;
}

TEST(TreeEstimators, EllipsoidEstimatorEqualsSphereEstimatorOnASphere) {
  Scene scene;
  scene.objects.push_back(sphere_cloud(3000, 1.0f, 6));
  SplitMix64 rng(8);
  std::vector<glm::vec3> p, n;
  for (int i = 0; i < 500; ++i) {
    p.push_back(rng.uniform(0.0f, 1.2f) * unit(rng));
    n.push_back(unit(rng));
  }
  const GBuffer g = probes(p, n, std::vector<float>(p.size(), 0.0f));
  // A derived sphere serves tree-ellipsoid when the scene says "sphere".
  TreeProxy given;
  given.type = "sphere";
  given.shapes.push_back(ellipsoid(glm::vec3(0.01f, 0.0f, 0.0f), glm::vec3(1.05f)));
  scene.objects[0].proxy = given;
  const auto s = estimate("tree-sphere", scene, g), e = estimate("tree-ellipsoid", scene, g);
  for (size_t k = 0; k < s.size(); ++k) EXPECT_NEAR(s[k], e[k], 1e-6);
}

// A 1 x 1 grass field of blades 0.4 high (with the generator's facts) and a 10 x 10 ground whose
// height is `slope` x.
Scene grass_on_ground(float slope) {
  nlohmann::json gp = {{"size", {1.0, 1.0}}, {"density", 50}, {"blade_height", 0.4}};
  JsonReader reader(gp, "test");
  SceneObject grass;
  grass.name = "grass";
  grass.role = Role::grass;
  GeneratedGeometry field = find_generator("grass")->function(1, reader);
  grass.mesh = std::move(field.mesh);
  grass.facts = std::move(field.facts);
  reader.finish();
  SceneObject ground;
  ground.name = "ground";
  ground.role = Role::ground;
  ground.mesh.positions = {
      {-5, -5 * slope, -5}, {5, 5 * slope, -5}, {5, 5 * slope, 5}, {-5, -5 * slope, 5}};
  ground.mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  Scene scene;
  scene.objects = {ground, grass};
  return scene;
}

TEST(TreeEstimators, GroundGrassAndSceneWithoutTrees) {
  // Grass field only (no trees): grass pixels follow eq. 9, the ground under it too, open ground 1.
  const Scene scene = grass_on_ground(0.0f);
  const glm::vec3 up(0, 1, 0);
  const GBuffer g =
      probes({{0.1f, 0.4f, 0.0f}, {0.1f, 0.1f, 0.0f}, {0.0f, 0.0f, 0.0f}, {3.0f, 0.0f, 0.0f}},
             {up, glm::vec3(1, 0, 0), up, up}, {1.0f, 1.0f, 0.0f, 0.0f});
  for (const char* name : {"tree-sphere", "tree-ellipsoid", "tree-shells"}) {
    const auto ao = estimate(name, scene, g);
    EXPECT_FLOAT_EQ(ao[0], 1.0f);
    EXPECT_FLOAT_EQ(ao[1], 0.1f / 0.8f);
    EXPECT_EQ(ao[2], 0.0f);
    EXPECT_EQ(ao[3], 1.0f);
    EXPECT_EQ(estimate(name, scene, g, {{"grass_ground", false}})[2], 1.0f);
  }
  const auto rb = estimate("reeves-blau", scene, g);
  for (float v : rb) EXPECT_EQ(v, 1.0f);
}

TEST(TreeEstimators, GrassOnATerrainMeasuresItsHeightFromTheTerrain) {
  // The field of the test above standing "on" the tilted ground y = x / 2 (each blade lifted by
  // the height under its root, as stand_on.h does): eq. 9's P_z is the height over the terrain
  // under the pixel, not over the field's lowest vertex (which is 0.25 below its centre).
  Scene scene = grass_on_ground(0.5f);
  SceneObject& grass = scene.objects[1];
  grass.on = "ground";
  for (size_t b = 0; b < grass.mesh.positions.size(); b += 7) {  // 3 segments: 7 vertices a blade
    const float h = 0.25f * (grass.mesh.positions[b].x + grass.mesh.positions[b + 1].x);
    for (size_t k = b; k < b + 7; ++k) grass.mesh.positions[k].y += h;
  }
  const glm::vec3 up(0, 1, 0);
  const GBuffer g = probes({{0.3f, 0.55f, 0.0f}, {0.3f, 0.25f, 0.0f}, {-0.4f, -0.2f, 0.0f}},
                           {up, glm::vec3(1, 0, 0), up}, {1.0f, 1.0f, 0.0f});
  for (const char* name : {"tree-sphere", "tree-ellipsoid", "tree-shells"}) {
    const auto ao = estimate(name, scene, g);
    EXPECT_NEAR(ao[0], 1.0f, 1e-5f);         // a tip facing up
    EXPECT_NEAR(ao[1], 0.1f / 0.8f, 1e-5f);  // 0.1 over the terrain, facing sideways
    EXPECT_NEAR(ao[2], 0.0f, 1e-5f);         // the ground at the roots
  }
}

TEST(TreeEstimators, GroundUnderATreeFollowsEq8) {
  Scene scene;
  scene.objects.push_back(sphere_cloud(1000, 1.0f, 2));
  for (auto& v : scene.objects[0].mesh.positions) v.y += 5.0f;
  TreeProxy given;
  given.type = "sphere";
  given.shapes.push_back(ellipsoid(glm::vec3(0.0f, 5.0f, 0.0f), glm::vec3(1.0f)));
  scene.objects[0].proxy = given;
  SceneObject ground;
  ground.name = "ground";
  ground.role = Role::ground;
  ground.mesh.positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}};
  ground.mesh.triangles = {{0, 2, 1}};
  scene.objects.push_back(ground);
  const GBuffer g = probes({glm::vec3(0.0f)}, {glm::vec3(0, 1, 0)}, {1.0f});
  EXPECT_NEAR(estimate("tree-sphere", scene, g)[0], 1.0 - 1.0 / 50.0, 1e-6);  // 1 - r^2 / (2 d^2)
  EXPECT_EQ(estimate("reeves-blau", scene, g)[0], 1.0f);
}

TEST(TreeEstimators, DeclareUniformUnboundedAndValidDefaults) {
  for (const char* name : {"tree-sphere", "tree-ellipsoid", "tree-shells", "reeves-blau"}) {
    const EstimatorInfo& info = find_estimator(name);
    const ParamSet p = resolve_params(info.name, info.params, nlohmann::json::object(), "test");
    const AoDefinition d = info.definition(p);
    EXPECT_EQ(d.weighting, Weighting::uniform) << name;
    EXPECT_FALSE(d.bounded()) << name;
    EXPECT_THROW(resolve_params(info.name, info.params, {{"alpha", 1}}, "test"), InputError);
  }
}

}  // namespace
}  // namespace aoeval
