// tree-volume against closed forms and independent quadratures (volume_model.h). The model is
// deterministic; tolerances are float rounding (a few ulps per direction summed over the direction
// set) plus, where the estimator's fixed product rule is compared with an exact integral, that
// rule's truncation error, computed in double in the test itself.
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "estimators/registry.h"
#include "estimators/tree_proxies/tree_proxy.h"
#include "estimators/tree_volume/volume_model.h"
#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

namespace vm = volume;
constexpr double kPi = 3.14159265358979323846;

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

Ellipsoid ellipsoid(glm::vec3 c, glm::vec3 r) {
  Ellipsoid e;
  e.center = c;
  e.radii = r;
  e.axes = glm::mat3(1.0f);
  return e;
}

GBuffer probes(const std::vector<glm::vec3>& p, const std::vector<glm::vec3>& n) {
  GBuffer g;
  g.width = static_cast<int>(p.size());
  g.height = 1;
  g.coverage.assign(p.size(), 1.0f);
  g.depth.assign(p.size(), 1.0f);
  g.position = p;
  g.normal = n;
  g.geometric_normal = n;
  g.object_id.assign(p.size(), 0.0f);
  return g;
}

std::vector<float> estimate(const Scene& scene, const GBuffer& g, const nlohmann::json& overrides) {
  const EstimatorInfo& info = find_estimator("tree-volume");
  EmbreeScene es(scene);
  const EstimateContext context{scene, es, g};
  auto e = info.create(resolve_params(info.name, info.params, overrides, "test"));
  e->prepare(context);
  return e->run(context).ao;
}

// One tree of uniform leaves with the given spherical (or shells) proxy; lambda = G A / V.
struct Ball {
  Scene scene;
  double lambda = 0.0;
};
Ball ball(float R) {
  Ball b;
  b.scene.objects.push_back(sphere_cloud(2000, 1.0f, 4));
  TreeProxy given;
  given.type = "sphere";
  given.shapes.push_back(ellipsoid(glm::vec3(0.0f), glm::vec3(R)));
  b.scene.objects[0].proxy = given;
  b.lambda = kLeafProjection * tree_leaves(b.scene.objects[0]).area / (4.0 / 3.0 * kPi * R * R * R);
  return b;
}

TEST(VolumeModel, GaussLegendreIsExactToDegreeTwoMMinusOne) {
  for (int m : {1, 2, 4, 7, 16}) {
    const vm::GaussLegendre g = vm::gauss_legendre(m);
    for (int p = 0; p <= 2 * m - 1; ++p) {
      double s = 0.0;
      for (int i = 0; i < m; ++i) s += g.weights[i] * std::pow(g.nodes[i], p);
      EXPECT_NEAR(s, 1.0 / (p + 1), 1e-13) << "m " << m << " degree " << p;
    }
  }
}

TEST(VolumeModel, DirectionSetIsAUnitHemisphereRuleWithTheWeightingsMoments) {
  for (bool cosine : {false, true}) {
    const vm::DirectionSet s = vm::direction_set(4, 8, cosine);
    double w = 0.0, mu = 0.0;
    for (size_t d = 0; d < s.dirs.size(); ++d) {
      EXPECT_NEAR(glm::length(s.dirs[d]), 1.0, 1e-6);
      EXPECT_GT(s.dirs[d].z, 0.0f);
      w += s.weights[d];
      mu += s.weights[d] * s.dirs[d].z;
    }
    EXPECT_NEAR(w, 1.0, 1e-6);
    // Mean cos(theta): 1/2 under uniform weighting, 2/3 under cosine (both exact for GL).
    EXPECT_NEAR(mu, cosine ? 2.0 / 3.0 : 0.5, 1e-6);
  }
}

TEST(VolumeModel, SphereChordIsTheClosedForm) {
  const glm::vec3 c(1.0f, -2.0f, 0.5f);
  const float R = 1.5f;
  const glm::vec3 q(0.3f, 0.4f, -0.2f), w = glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f));
  const float b = glm::dot(q, w);
  EXPECT_NEAR(vm::sphere_chord(c + q, w, c, R), std::sqrt(R * R - glm::dot(q, q) + b * b) - b,
              1e-6);
  EXPECT_NEAR(vm::sphere_chord(c, w, c, R), R, 1e-6);
  // From outside: through the whole sphere when aimed at it, nothing when aimed away.
  EXPECT_NEAR(vm::sphere_chord(c - 3.0f * w, w, c, R), 2.0f * R, 1e-5);
  EXPECT_EQ(vm::sphere_chord(c + 3.0f * w, w, c, R), 0.0f);
}

// The first closed form: at the centre every chord is R, so V = exp(-lambda R) for any
// normal, weighting and direction count (the weights sum to 1; float rounding only).
TEST(TreeVolume, CentreOfAUniformSphereIsExpMinusLambdaR) {
  const float R = 1.2f;
  const Ball b = ball(R);
  const GBuffer g =
      probes({glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)},
             {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, 2, 3)), glm::vec3(0, 0, -1)});
  for (const char* weighting : {"uniform", "cosine"})
    for (int rings : {1, 4, 9})
      for (const char* proxy : {"sphere", "ellipsoid"}) {
        const auto ao =
            estimate(b.scene, g, {{"weighting", weighting}, {"rings", rings}, {"proxy", proxy}});
        for (float v : ao)
          EXPECT_NEAR(v, std::exp(-b.lambda * R), 1e-6) << weighting << " " << rings << proxy;
      }
  // lambda_scale multiplies lambda.
  EXPECT_NEAR(estimate(b.scene, g, {{"lambda_scale", 2.0}})[0], std::exp(-2.0 * b.lambda * R),
              1e-6);
}

// The second: at distance x from the centre with the outward normal, the integrand depends
// on mu = cos(theta) only, chord(mu) = sqrt(R^2 - x^2 (1 - mu^2)) - x mu, and
//     V_uniform = Int_0^1 exp(-lambda chord) dmu,   V_cosine = Int_0^1 2 mu exp(-lambda chord) dmu.
// "exact" is composite Simpson with 20,000 intervals in double (error ~ h^4 f'''' < 1e-12 here).
// The estimator applies `rings`-node Gauss-Legendre in mu; its truncation error for this integrand,
// |GL_rings - exact|, is computed here in double, and the float evaluation adds at most a few ulps
// per direction (32 to 128 directions: < 2e-6). At 16 rings the rule's own error is below 1e-9,
// so there the estimator must match the exact integral to rounding.
TEST(TreeVolume, OffCentreWithOutwardNormalMatchesAnIndependentQuadrature) {
  const float R = 1.2f;
  const Ball b = ball(R);
  const double lambda = b.lambda;
  auto f = [&](double mu, double x, bool cosine) {
    const double chord = std::sqrt(R * R - x * x * (1.0 - mu * mu)) - x * mu;
    return (cosine ? 2.0 * mu : 1.0) * std::exp(-lambda * chord);
  };
  auto simpson = [&](double x, bool cosine) {
    const int n = 20000;
    double s = f(0.0, x, cosine) + f(1.0, x, cosine);
    for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(double(i) / n, x, cosine);
    return s / (3.0 * n);
  };
  auto gl = [&](int m, double x, bool cosine) {
    const vm::GaussLegendre q = vm::gauss_legendre(m);
    double s = 0.0;
    for (int i = 0; i < m; ++i) s += q.weights[i] * f(q.nodes[i], x, cosine);
    return s;
  };
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f));
  for (double frac : {0.25, 0.6, 0.95}) {
    const double x = frac * R;
    const GBuffer g = probes({static_cast<float>(x) * axis}, {axis});
    for (bool cosine : {false, true}) {
      const double exact = simpson(x, cosine);
      const char* w = cosine ? "cosine" : "uniform";
      for (int rings : {4, 16}) {
        const double truncation = std::fabs(gl(rings, x, cosine) - exact);
        if (rings == 16) {
          EXPECT_LT(truncation, 1e-9);
        }
        const float v = estimate(b.scene, g, {{"weighting", w}, {"rings", rings}})[0];
        EXPECT_NEAR(v, exact, truncation + 2e-6) << w << " x/R " << frac << " rings " << rings;
      }
    }
  }
  // Not a free pass: eq. 6 (tree-sphere) at the same point differs by far more than that.
  const GBuffer rim = probes({0.95f * R * axis}, {axis});
  const float eq6 = estimate(b.scene, rim, {{"rings", 16}})[0];
  const auto& sphere = find_estimator("tree-sphere");
  EmbreeScene es(b.scene);
  auto e = sphere.create(resolve_params(sphere.name, sphere.params, {}, "test"));
  const EstimateContext context{b.scene, es, rim};
  e->prepare(context);
  EXPECT_GT(std::fabs(e->run(context).ao[0] - eq6), 0.01);
}

// Any point and normal: the estimator equals its direction set applied to the chord, here computed
// by marching the ray in double (step 1e-4: each chord is off by at most 2 steps, so exp(-lambda
// chord) by lambda 2e-4); shells through a union of two overlapping spheres (cells split at the
// bisecting plane, so the union's chord), with the scene's density giving both the same lambda.
TEST(TreeVolume, AnyPointMatchesMarchedChordsThroughSphereAndShells) {
  Scene scene;
  scene.objects.push_back(sphere_cloud(2000, 1.0f, 4));
  scene.objects[0].density = 200.0;
  const double lambda =
      kLeafProjection * 200.0 * tree_leaves(scene.objects[0]).area / 2000.0;  // tree_proxy.h
  const glm::dvec3 c1(-0.5, 0.0, 0.0), c2(0.5, 0.1, 0.0);
  const double R = 1.0;
  TreeProxy shells;
  shells.type = "shells";
  shells.shapes = {ellipsoid(glm::vec3(c1), glm::vec3(R)), ellipsoid(glm::vec3(c2), glm::vec3(R))};
  auto inside = [&](const glm::dvec3& p, bool both) {
    return glm::length(p - c1) <= R || (both && glm::length(p - c2) <= R);
  };
  auto marched = [&](const glm::vec3& x, const glm::vec3& n, bool both) {
    const vm::DirectionSet s = vm::direction_set(3, 6, false);
    const glm::mat3 f = vm::frame(n);
    double v = 0.0;
    const double step = 1e-4;
    for (size_t d = 0; d < s.dirs.size(); ++d) {
      const glm::dvec3 w(f * s.dirs[d]);
      double chord = 0.0;
      for (double t = 0.5 * step; t < 4.0; t += step)
        if (inside(glm::dvec3(x) + t * w, both)) chord += step;
      v += s.weights[d] * std::exp(-lambda * chord);
    }
    return v;
  };
  const std::vector<glm::vec3> p = {{-0.7f, 0.2f, 0.1f}, {-0.1f, -0.3f, 0.4f}, {0.9f, 0.0f, 0.2f}};
  const std::vector<glm::vec3> n = {glm::normalize(glm::vec3(1, 1, 0)),
                                    glm::normalize(glm::vec3(-1, 0.2f, 0.5f)),
                                    glm::normalize(glm::vec3(0, -1, 1))};
  const double tol = lambda * 2e-4 + 2e-6;
  for (bool both : {false, true}) {
    TreeProxy proxy = shells;
    if (!both) {
      proxy.shapes.pop_back();
      proxy.type = "sphere";
    }
    scene.objects[0].proxy = proxy;
    const auto ao =
        estimate(scene, probes(p, n),
                 {{"proxy", both ? "shells" : "sphere"}, {"rings", 3}, {"azimuths", 6}});
    for (size_t k = 0; k < p.size(); ++k)
      EXPECT_NEAR(ao[k], marched(p[k], n[k], both), tol) << (both ? "shells " : "sphere ") << k;
  }
}

TEST(TreeVolume, DeterministicDeclaredAndOpenOutsideTheCrown) {
  const Ball b = ball(1.0f);
  // On the envelope facing out every chord is 0: fully open.
  const GBuffer g = probes({glm::vec3(0, 1, 0), glm::vec3(0.3f, 0.2f, 0.1f)},
                           {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, -1, 2))});
  const auto a = estimate(b.scene, g, {}), c = estimate(b.scene, g, {});
  EXPECT_NEAR(a[0], 1.0f, 1e-6);
  EXPECT_EQ(a[1], c[1]);
  const EstimatorInfo& info = find_estimator("tree-volume");
  const ParamSet p = resolve_params(info.name, info.params, nlohmann::json::object(), "test");
  EXPECT_EQ(info.definition(p).weighting, Weighting::uniform);
  EXPECT_FALSE(info.definition(p).bounded());
  EXPECT_EQ(
      info.definition(resolve_params(info.name, info.params, {{"weighting", "cosine"}}, "test"))
          .weighting,
      Weighting::cosine);
  EXPECT_THROW(resolve_params(info.name, info.params, {{"alpha_rho", 1}}, "test"), InputError);
}

}  // namespace
}  // namespace aoeval
