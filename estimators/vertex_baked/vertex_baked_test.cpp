// vertex-baked against closed forms and against the per-pixel reference. Statistical tolerances
// come from the ray counts: a vertex value is an area-weighted mean of its triangles' binomial
// means, so its standard error is sqrt(p (1 - p) sum(w_t^2) / rays) with w_t the normalised areas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "base/errors.h"
#include "estimators/registry.h"
#include "estimators/vertex_baked/vertex_bake.h"
#include "estimators/vertex_baked/vertex_baked.h"
#include "references/reference.h"
#include "scenes/analytic_scenes.h"
#include "scenes/generators/generators.h"

namespace aoeval {
namespace {

GBuffer gbuffer_of(const EmbreeScene& es, glm::vec3 eye, glm::vec3 target, glm::vec3 up, int w,
                   int h, float fov = 45.0f) {
  View v;
  v.eye = eye, v.target = target, v.up = up, v.fov_y_deg = fov, v.width = w, v.height = h;
  return render_gbuffer(es, make_camera(v));
}

BakeSettings settings(int rays, int subdivide = 0, SamplerKind k = SamplerKind::random) {
  BakeSettings s{};
  s.seed = default_params(vertex_baked_estimator()).integer("seed");
  s.rays = rays;
  s.subdivide = subdivide;
  s.sampler = k;
  return s;
}

// The estimator through its declaration, as the harness runs it.
EstimateResult estimate(const Scene& scene, const EmbreeScene& es, const GBuffer& g,
                        nlohmann::json overrides) {
  const EstimatorInfo& e = find_estimator("vertex-baked");
  auto est = e.create(resolve_params(e.name, e.params, overrides, "test"));
  const EstimateContext context{scene, es, g};
  est->prepare(context);
  return est->run(context);
}

TEST(VertexBaked, DeclaresUniformUnboundedAccessibility) {
  const EstimatorInfo& e = find_estimator("vertex-baked");
  const AoDefinition d = e.definition(resolve_params(e.name, e.params, {}, "test"));
  EXPECT_EQ(d.weighting, Weighting::uniform);
  EXPECT_FALSE(d.bounded());
  EXPECT_EQ(d.falloff, Falloff::none);
}

TEST(VertexBaked, OpenPlaneBakesToExactlyOneOnBothSides) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {4, 4}}, {"subdivisions", 3}})});
  EmbreeScene es(s);
  for (int sub : {0, 1}) {
    const VertexBake b = bake_vertices(s, es, settings(64, sub));
    for (int side = 0; side < 2; ++side)
      for (size_t v = 0; v < b.objects[0].positions.size(); ++v) {
        ASSERT_EQ(b.objects[0].accessibility[side][v], 1.0f);
        // The mean of 64 uniform directions: (0, 1/2, 0) +- 0.072 per horizontal axis (variance 1/3
        // per ray); 4 standard errors leave the normalised direction within cos > 0.77 of the axis.
        const glm::vec3 bent = glm::normalize(b.objects[0].bent[side][v]);
        EXPECT_GT(side == 0 ? bent.y : -bent.y, 0.7f);
      }
  }
  // From above (front) and from below (back), every pixel is 1 up to barycentric rounding.
  for (float y : {2.0f, -2.0f}) {
    const GBuffer g = gbuffer_of(es, {0.3f, y, 0.5f}, {0, 0, 0}, {0, 0, -1}, 24, 16);
    const EstimateResult r = estimate(s, es, g, {{"rays", 64}});
    for (size_t k = 0; k < g.pixel_count(); ++k) {
      if (!g.covered(k)) continue;
      EXPECT_NEAR(r.ao[k], 1.0f, 1e-6f);
    }
  }
}

TEST(VertexBaked, InsideAClosedBoxIsZeroOutsideIsOne) {
  Scene s = scene_of({generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}})});
  EmbreeScene es(s);
  const VertexBake b = bake_vertices(s, es, settings(64));
  for (size_t v = 0; v < b.objects[0].positions.size(); ++v) {
    EXPECT_EQ(b.objects[0].accessibility[0][v], 0.0f);  // front = inward
    EXPECT_EQ(b.objects[0].bent[0][v], glm::vec3(0.0f));
    EXPECT_EQ(b.objects[0].accessibility[1][v], 1.0f);  // the outside of a lone box is open
  }
  // The lookup reads the viewer's side: 0 from inside, 1 from outside.
  const GBuffer inside = gbuffer_of(es, {0.2f, 1.1f, 0.3f}, {-1, 0.5f, -1}, {0, 1, 0}, 24, 16, 90);
  const EstimateResult ri = estimate(s, es, inside, {{"rays", 64}});
  for (size_t k = 0; k < inside.pixel_count(); ++k) {
    ASSERT_TRUE(inside.covered(k));
    EXPECT_EQ(ri.ao[k], 0.0f);
  }
  const GBuffer outside = gbuffer_of(es, {3, 3, 4}, {0, 1, 0}, {0, 1, 0}, 24, 16);
  const EstimateResult ro = estimate(s, es, outside, {{"rays", 64}});
  for (size_t k = 0; k < outside.pixel_count(); ++k) {
    if (!outside.covered(k)) continue;
    EXPECT_NEAR(ro.ao[k], 1.0f, 1e-6f);
  }
}

// A small floor under a parallel disk of radius a at height h (cf. references/reference_test.cpp
// DiskAbovePlane). The floor is 0.002 wide in a 2 x 2 grid, so its centre vertex, at the disk's
// axis, averages 6 triangles whose centres lie within 1e-3 of it: accessibility is even in the
// offset r with curvature O(1/h^2), so that bias is O(1e-6), far below the tolerance.
class DiskAbovePlane : public ::testing::Test {
 protected:
  static constexpr double a = 1.0, h = 0.5;
  DiskAbovePlane()
      : scene_(scene_of(
            {generated("floor", "plane", {{"size", {0.002, 0.002}}, {"subdivisions", 2}}),
             generated("disk", "disk", {{"radius", a}, {"segments", 256}, {"facing", "down"}},
                       {0.0f, static_cast<float>(h), 0.0f})})),
        es_(scene_) {}
  // The floor vertex at the origin.
  static size_t centre_vertex(const BakedMesh& m) {
    for (size_t v = 0; v < m.positions.size(); ++v)
      if (m.positions[v] == glm::vec3(0.0f)) return v;
    ADD_FAILURE() << "no vertex at the origin";
    return 0;
  }
  // sum(w_t^2) over the triangles incident to vertex v, w_t their normalised areas.
  static double sum_w2(const BakedMesh& m, size_t v) {
    std::vector<double> areas;
    for (const auto& t : m.triangles)
      if (t.x == v || t.y == v || t.z == v)
        areas.push_back(0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x],
                                                     m.positions[t.z] - m.positions[t.x])));
    double total = 0.0, s2 = 0.0;
    for (double x : areas) total += x;
    for (double x : areas) s2 += (x / total) * (x / total);
    return s2;
  }
  Scene scene_;
  EmbreeScene es_;
};

TEST_F(DiskAbovePlane, CentreVertexMatchesTheUniformClosedForm) {
  // Uniform weighting: the disk covers a cone of half-angle alpha, tan(alpha) = a / h, so
  // AO = cos(alpha) = h / sqrt(a^2 + h^2). The inscribed 256-gon lies between radii a cos(pi/256)
  // and a: AO is at most 3.1e-5 higher, added to the tolerance.
  const double exact = h / std::sqrt(a * a + h * h);
  const double polygon = h / std::sqrt(a * a * std::pow(std::cos(M_PI / 256), 2) + h * h) - exact;
  const int rays = 4096;
  for (SamplerKind k : {SamplerKind::random, SamplerKind::stratified}) {
    const VertexBake b = bake_vertices(scene_, es_, settings(rays, 0, k));
    const BakedMesh& floor = b.objects[0];
    const size_t v = centre_vertex(floor);
    // Random: the binomial standard error. Stratified (systematic): its error on an indicator with
    // a smooth boundary shrinks faster than 1/sqrt(rays), so the random bound is conservative.
    const double se = std::sqrt(exact * (1.0 - exact) * sum_w2(floor, v) / rays);
    EXPECT_NEAR(floor.accessibility[0][v], exact + 0.5 * polygon, 4.0 * se + 0.5 * polygon)
        << sampler_name(k);
    // The unoccluded directions are symmetric about the axis: the bent normal is +Y.
    EXPECT_GT(glm::normalize(floor.bent[0][v]).y, 0.99f);
  }
}

TEST(VertexBaked, ALoneTriangleBakesAtItsCentre) {
  // One floor triangle, its centre on the axis of the disk of DiskAbovePlane, its corners 0.6 to
  // 0.9 off it: each corner takes the triangle's value, which is the closed form at the centre (a
  // bake at any other point of it would be brighter by several standard errors).
  SceneObject tri;
  tri.name = "triangle";
  tri.mesh.positions = {{-0.6f, 0, -0.4f}, {-0.4f, 0, 0.6f}, {1.0f, 0, -0.2f}};  // centre 0, up
  tri.mesh.triangles = {{0, 1, 2}};
  const double a = 1.0, h = 0.5;
  Scene s = scene_of(
      {tri, generated("disk", "disk", {{"radius", a}, {"segments", 256}, {"facing", "down"}},
                      {0.0f, static_cast<float>(h), 0.0f})});
  EmbreeScene es(s);
  const int rays = 4096;
  const VertexBake b = bake_vertices(s, es, settings(rays));
  const double exact = h / std::sqrt(a * a + h * h);
  const double polygon = h / std::sqrt(a * a * std::pow(std::cos(M_PI / 256), 2) + h * h) - exact;
  const double se = std::sqrt(exact * (1.0 - exact) / rays);
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(b.objects[0].accessibility[0][v], b.objects[0].accessibility[0][0]);
    EXPECT_EQ(b.objects[0].accessibility[1][v], 1.0f);  // below the triangle nothing occludes
  }
  EXPECT_NEAR(b.objects[0].accessibility[0][0], exact + 0.5 * polygon, 4.0 * se + 0.5 * polygon);
}

TEST(VertexBaked, VerticesAverageTheirTrianglesByArea) {
  // A bow-tie: triangles A (small, under a disk) and B (large, mostly outside its shadow) share
  // vertex 0 only, so vertices 1 and 3 hold A's and B's own values and vertex 0 their area-weighted
  // mean, exactly up to rounding, whatever the noise.
  SceneObject tie;
  tie.name = "bow-tie";
  tie.mesh.positions = {{0, 0, 0},
                        {-0.2f, 0, 0.1f},
                        {-0.1f, 0, -0.2f},  // A: area 0.025
                        {3.0f, 0, -1.0f},
                        {2.0f, 0, 2.0f}};       // B: area 4
  tie.mesh.triangles = {{0, 2, 1}, {0, 4, 3}};  // both face +Y
  Scene s = scene_of(
      {tie, generated("disk", "disk", {{"radius", 1.0}, {"facing", "down"}}, {0.0f, 0.5f, 0.0f})});
  EmbreeScene es(s);
  const VertexBake b = bake_vertices(s, es, settings(256));
  const auto& acc = b.objects[0].accessibility[0];
  ASSERT_LT(acc[1], acc[3] - 0.1f);  // the disk shades A far more than B
  EXPECT_NEAR(acc[0], (0.025 * acc[1] + 4.0 * acc[3]) / 4.025, 1e-6);
  EXPECT_EQ(acc[2], acc[1]);
  EXPECT_EQ(acc[4], acc[3]);
}

TEST_F(DiskAbovePlane, PixelAtAVertexReadsThatVertex) {
  // A 3 x 3 image looking straight down: the centre pixel's ray is the view axis, through the
  // floor vertex at the origin.
  const GBuffer g = gbuffer_of(es_, {0, 0.25f, 0}, {0, 0, 0}, {0, 0, -1}, 3, 3, 0.01f);
  const EstimateResult r = estimate(scene_, es_, g, {{"rays", 256}});
  const VertexBake b = bake_vertices(scene_, es_, settings(256));  // the estimator's own bake
  const size_t v = centre_vertex(b.objects[0]);
  ASSERT_TRUE(g.covered(g.index(1, 1)));
  EXPECT_NEAR(r.ao[g.index(1, 1)], b.objects[0].accessibility[0][v], 1e-6f);
}

TEST_F(DiskAbovePlane, LookupInterpolatesVertexValues) {
  for (int sub : {0, 1, 2}) {
    const VertexBake b = bake_vertices(scene_, es_, settings(64, sub));
    const BakedMesh& m = b.objects[0];
    const auto& acc = m.accessibility[0];
    for (unsigned prim = 0; prim < 8; ++prim) {
      // The first sub-triangle of `prim` is its corner-0 child at every level, and so on: its
      // corners are p0 of the original and the midpoints towards p1 and p2, 2^-sub along.
      const size_t first = static_cast<size_t>(prim) << (2 * sub);
      const glm::uvec3 t = m.triangles[first];
      const float e = std::ldexp(1.0f, -sub);
      EXPECT_EQ(lookup(b, 0, prim, 0.0f, 0.0f, 0).accessibility, acc[t.x]);
      EXPECT_EQ(lookup(b, 0, prim, e, 0.0f, 0).accessibility, acc[t.y]);
      EXPECT_EQ(lookup(b, 0, prim, 0.0f, e, 0).accessibility, acc[t.z]);
      // Its centre: the mean of its three corners.
      const float mean = (acc[t.x] + acc[t.y] + acc[t.z]) / 3.0f;
      EXPECT_NEAR(lookup(b, 0, prim, e / 3.0f, e / 3.0f, 0).accessibility, mean, 1e-6f);
    }
  }
}

// The convergence the chapter's "finely tessellated" assumption rests on: an 80-face sphere on a
// floor of two triangles (its contact shadow lies inside them), against the per-pixel uniform
// reference. The reference orients by the geometric normal, as the bake does, so that the error
// left is the interpolation's alone (the sphere's smooth shading normals would add a constant).
//
// Statistics, in mean squares so that noise terms add: D = mean((est - ref)^2) - mean(ref
// stderr^2) estimates E^2 + M, with E the rms error of the noise-free bake and M >= 0 the mean
// bake variance per pixel, at most 0.25 / rays (a convex combination of binomial means). Its
// fluctuation over bake seeds is measured with 4 seeds per level; the reference noise is shared by
// every level and moves D_l - D_l+1 by -2 mean((est_l - est_l+1) r), whose standard deviation is
// computed from the reference's stderr. A fall of E^2 is shown when the fall of D exceeds
// 0.25 / rays plus 4 standard deviations of all that noise. (Measured: D
// falls 1.7e-2, 6.2e-3, 1.9e-3, 2.9e-4 over the four levels; the largest margin is 6e-4, against a
// smallest fall of 1.6e-3.)
TEST(VertexBaked, ErrorFallsAsTessellationRises) {
  Scene s = scene_of(
      {generated("floor", "plane", {{"size", {2, 2}}}),
       generated("sphere", "sphere", {{"radius", 0.5}, {"subdivisions", 1}}, {0, 0.5f, 0})});
  EmbreeScene es(s);
  const GBuffer g = gbuffer_of(es, {1.0f, 1.4f, 2.0f}, {0, 0.2f, 0}, {0, 1, 0}, 96, 72);
  ReferenceSettings rs;
  rs.sampler = SamplerKind::random;
  rs.spp = 1024;
  rs.definition.weighting = Weighting::uniform;
  rs.normal = NormalMode::geometric;
  const ReferenceImage ref = compute_reference(es, g, rs);
  std::vector<size_t> px;
  double ref_ms = 0.0;
  for (size_t k = 0; k < g.pixel_count(); ++k)
    if (g.covered(k)) px.push_back(k), ref_ms += double(ref.stderr_ao[k]) * ref.stderr_ao[k];
  const double n = static_cast<double>(px.size());
  ref_ms /= n;
  const int rays = 512, seeds = 4, levels = 4;
  std::vector<double> mean(levels), var_of_mean(levels);
  std::vector<std::vector<double>> est(levels, std::vector<double>(px.size(), 0.0));
  for (int sub = 0; sub < levels; ++sub) {
    std::vector<double> d;
    for (int seed = 1; seed <= seeds; ++seed) {
      const EstimateResult r =
          estimate(s, es, g, {{"rays", rays}, {"subdivide", sub}, {"seed", seed}});
      double sq = 0.0;
      for (size_t i = 0; i < px.size(); ++i) {
        sq += std::pow(double(r.ao[px[i]]) - ref.ao[px[i]], 2.0);
        est[sub][i] += r.ao[px[i]] / seeds;
      }
      d.push_back(sq / n - ref_ms);
    }
    for (double x : d) mean[sub] += x / seeds;
    for (double x : d) var_of_mean[sub] += std::pow(x - mean[sub], 2.0) / (seeds - 1) / seeds;
    std::printf("subdivide %d: rmse excess %.4f (D = %.2e +- %.1e)\n", sub,
                std::sqrt(std::max(0.0, mean[sub])), mean[sub], std::sqrt(var_of_mean[sub]));
  }
  for (int sub = 0; sub + 1 < levels; ++sub) {
    double ref_var = 0.0;  // of -2 mean((est_l - est_l+1) r)
    for (size_t i = 0; i < px.size(); ++i)
      ref_var += std::pow(2.0 * (est[sub][i] - est[sub + 1][i]) * ref.stderr_ao[px[i]] / n, 2.0);
    const double margin =
        0.25 / rays + 4.0 * std::sqrt(var_of_mean[sub] + var_of_mean[sub + 1] + ref_var);
    EXPECT_GT(mean[sub] - mean[sub + 1], margin) << "subdivide " << sub << " -> " << sub + 1;
  }
}

TEST(VertexBaked, SameSeedSameBits) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {4, 4}}}),
                      generated("box", "box", {{"size", {1, 1, 1}}})});
  EmbreeScene es(s);
  const GBuffer g = gbuffer_of(es, {1.2f, 1.6f, 2.6f}, {0, 0.3f, 0}, {0, 1, 0}, 48, 36);
  for (const char* sampler : {"random", "stratified", "sobol"}) {
    const nlohmann::json p = {{"rays", 32}, {"subdivide", 2}, {"sampler", sampler}};
    const EstimateResult a = estimate(s, es, g, p), b = estimate(s, es, g, p);
    ASSERT_EQ(a.ao.size(), b.ao.size());
    EXPECT_EQ(std::memcmp(a.ao.data(), b.ao.data(), a.ao.size() * sizeof(float)), 0) << sampler;
    for (const char* c : {"bent.X", "bent.Y", "bent.Z"})
      EXPECT_EQ(std::memcmp(a.extra_channels.at(c).data(), b.extra_channels.at(c).data(),
                            a.ao.size() * sizeof(float)),
                0)
          << sampler << " " << c;
    nlohmann::json q = p;
    q["seed"] = 8;
    const EstimateResult c = estimate(s, es, g, q);
    EXPECT_NE(std::memcmp(a.ao.data(), c.ao.data(), a.ao.size() * sizeof(float)), 0) << sampler;
  }
}

TEST(VertexBaked, TooManySubdividedTrianglesIsAnInputErrorNamingSubdivide) {
  Scene s = scene_of({generated("floor", "plane", {{"size", {4, 4}}, {"subdivisions", 128}})});
  EXPECT_NO_THROW(check_subdivide(s, 5));  // 2^15 * 4^5 = 2^25 triangles: the limit itself
  try {
    check_subdivide(s, 6);  // 2^27
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("subdivide=6"), std::string::npos) << e.what();
  }
}

TEST(VertexBaked, SubdivisionSharesMidpointsAndKeepsWinding) {
  TriangleMesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  const TriangleMesh m = subdivide_mesh(quad, 2);
  EXPECT_EQ(m.triangles.size(), 32u);
  EXPECT_EQ(m.positions.size(), 25u);  // a 5 x 5 grid: the shared diagonal's midpoints once
  for (const auto& t : m.triangles) {
    const glm::vec3 n =
        glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    EXPECT_GT(n.y, 0.0f);  // the parents face +Y, and so does every child
  }
}

}  // namespace
}  // namespace aoeval
