// Conformance: every registered estimator (CPU, Embree, Vulkan on lavapipe) on analytic scenes,
// run as the harness runs it (declared defaults, prepare, run, estimate_to_image). A new estimator
// is checked here without a line of test code; what it may be expected to do comes from its
// EstimatorInfo::conformance, whose defaults follow from its backend.
//   - The corpus's open-plane: AO within open_plane_tolerance() of 1 (no occluder above a lone
//     plane), the tolerance each estimator declares (EstimatorInfo::conformance, a plug-in's
//     estimator.json open_plane_tolerance) or its backend's default.
//   - Inside a closed box: AO at most the definition's ray value at the box's diagonal (every ray
//     hits a wall no farther away), for estimators that see the whole enclosure.
//   - Every scene, a tree scene included: AO finite and in [0, 1] on covered pixels, 0 on uncovered
//     ones in the image the harness writes; the same seed gives the same bits.
// Tree estimators (tree-sphere, tree-ellipsoid, tree-shells, reeves-blau) join through the tree
// scene (a sphere-uniform leaf ball with the tree role above a ground plane), where they derive
// their proxies; on the open plane and in the box they have no tree and must see open sky.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <optional>

#include "estimators/registry.h"
#include "estimators/testing/registry_test_names.h"
#include "harness/evaluation/evaluation.h"
#include "scenes/analytic_scenes.h"
#include "scenes/corpus.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {
namespace {

constexpr int kW = 48, kH = 36;

struct Analytic {
  Scene scene;
  std::unique_ptr<EmbreeScene> embree;
  GBuffer gbuffer;
};

// Built in place and never moved: the Embree scene refers to the scene. Rendered from the scene's
// first view at kW x kH.
std::unique_ptr<const Analytic> make(Scene scene) {
  auto a = std::make_unique<Analytic>();
  a->scene = std::move(scene);
  a->embree = std::make_unique<EmbreeScene>(a->scene);
  a->gbuffer = render_gbuffer(*a->embree, make_camera(a->scene.views.front(), kW, kH));
  return a;
}

std::unique_ptr<const Analytic> make(Scene scene, glm::vec3 eye, glm::vec3 target) {
  View& v = scene.views.front();
  v.name = "main";
  v.eye = eye;
  v.target = target;
  v.fov_y_deg = 60.0f;
  return make(std::move(scene));
}

// The corpus's open-plane (a 4 x 4 plane seen from above at an angle: the far part of the image is
// sky, uncovered), so what users run `aoeval` on is what the registry is held to.
const Analytic& open_plane() {
  static const auto a = make(load_scene("open-plane"));
  return *a;
}

// The inside of a closed 0.2 box (it stands on y = 0), from near its centre: every pixel covered,
// every ray hits a wall within the box's diagonal.
constexpr double kBoxSize = 0.2;
const Analytic& closed_box() {
  static const auto a = make(
      scene_of(
          {generated("box", "box", {{"size", {kBoxSize, kBoxSize, kBoxSize}}, {"inward", true}})}),
      {0, 0.1f, 0.05f}, {0, 0.1f, -1});
  return *a;
}

// A leaf ball (tree role) above a ground plane: the scene the tree estimators derive proxies from.
const Analytic& tree_scene() {
  static const auto a = [] {
    SceneObject ground = generated("ground", "plane", {{"size", {6, 6}}});
    ground.role = Role::ground;
    SceneObject crown =
        generated("crown", "sphere-uniform",
                  {{"count", 1500}, {"radius", 0.6}, {"triangle_size", 0.08}}, {0, 1.0f, 0});
    crown.role = Role::tree;
    return make(scene_of({std::move(ground), std::move(crown)}), {0, 1.0f, 3.2f}, {0, 0.7f, 0});
  }();
  return *a;
}

struct Outcome {
  EstimateResult result;
  OIIO::ImageBuf image;  // as the harness writes it
};

// The estimator at its declared defaults; GTEST_SKIP when its backend is missing here.
std::optional<Outcome> run(const EstimatorInfo& e, const Analytic& a) {
  const ParamSet params = default_params(e);
  std::unique_ptr<Estimator> est = e.create(params);
  const EstimateContext context{a.scene, *a.embree, a.gbuffer};
  try {
    est->prepare(context);
    Outcome r;
    r.result = est->run(context);
    r.image = estimate_to_image(a.gbuffer, r.result);
    return r;
  } catch (const EstimatorUnavailable&) {
    return std::nullopt;
  }
}

#define RUN_OR_SKIP(var, e, a)                  \
  const std::optional<Outcome> var = run(e, a); \
  if (!var) GTEST_SKIP() << e.name << ": backend unavailable on this machine"

class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  const EstimatorInfo& info() const { return find_estimator(GetParam()); }
};

// Covered pixels finite and in [0, 1]; uncovered pixels 0 in the written image.
void expect_valid(const EstimatorInfo& e, const Analytic& a, const Outcome& r, const char* scene) {
  const GBuffer& g = a.gbuffer;
  ASSERT_EQ(r.result.ao.size(), g.pixel_count()) << e.name << " " << scene;
  std::vector<float> px(g.pixel_count() * r.image.spec().nchannels);
  r.image.get_pixels(OIIO::ROI::All(), OIIO::TypeFloat, px.data());
  const size_t nc = r.image.spec().nchannels;
  size_t bad = 0, nonzero_uncovered = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    const float v = px[k * nc];
    if (g.covered(k))
      bad += !(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    else
      nonzero_uncovered += v != 0.0f;
  }
  EXPECT_EQ(bad, 0u) << e.name << " " << scene << ": covered pixels outside [0, 1] or not finite";
  EXPECT_EQ(nonzero_uncovered, 0u) << e.name << " " << scene << ": uncovered pixels not 0";
}

TEST_P(Conformance, OpenPlaneIsUnoccluded) {
  const EstimatorInfo& e = info();
  const Analytic& a = open_plane();
  size_t covered = 0;
  for (size_t k = 0; k < a.gbuffer.pixel_count(); ++k) covered += a.gbuffer.covered(k);
  ASSERT_GT(covered, 0u);
  ASSERT_LT(covered, a.gbuffer.pixel_count());  // sky too, for the uncovered check
  RUN_OR_SKIP(r, e, a);
  expect_valid(e, a, *r, "open plane");
  const double tol = e.open_plane_tolerance();
  double worst = 0.0;
  for (size_t k = 0; k < a.gbuffer.pixel_count(); ++k)
    if (a.gbuffer.covered(k)) worst = std::max(worst, std::abs(1.0 - r->result.ao[k]));
  EXPECT_LE(worst, tol) << e.name << ": open plane, largest |AO - 1| (declared tolerance " << tol
                        << ")";
}

TEST_P(Conformance, ClosedBoxInteriorIsOccluded) {
  const EstimatorInfo& e = info();
  const Analytic& a = closed_box();
  RUN_OR_SKIP(r, e, a);
  expect_valid(e, a, *r, "closed box");
  if (!e.sees_enclosure())
    GTEST_SKIP() << e.name << " does not see a whole enclosure (EstimatorInfo::sees_enclosure)";
  // Every ray from a wall hits another wall within the diagonal, so AO <= ray_value(diagonal).
  const AoDefinition d = e.definition(default_params(e));
  const double bound = d.ray_value(static_cast<float>(kBoxSize * std::sqrt(3.0)));
  const double tol = e.open_plane_tolerance();
  double worst = 0.0;
  for (size_t k = 0; k < a.gbuffer.pixel_count(); ++k)
    if (a.gbuffer.covered(k)) worst = std::max(worst, double(r->result.ao[k]));
  EXPECT_LE(worst, bound + tol) << e.name << ": inside a closed box (bound " << bound << ")";
}

TEST_P(Conformance, TreeSceneOutputIsValid) {
  const EstimatorInfo& e = info();
  RUN_OR_SKIP(r, e, tree_scene());
  expect_valid(e, tree_scene(), *r, "tree scene");
}

TEST_P(Conformance, SameSeedSameBits) {
  const EstimatorInfo& e = info();
  for (const Analytic* a : {&open_plane(), &tree_scene()}) {
    RUN_OR_SKIP(first, e, *a);
    const std::optional<Outcome> second = run(e, *a);
    ASSERT_TRUE(second);
    ASSERT_EQ(first->result.ao.size(), second->result.ao.size());
    EXPECT_EQ(std::memcmp(first->result.ao.data(), second->result.ao.data(),
                          first->result.ao.size() * sizeof(float)),
              0)
        << e.name << ": two runs with the same parameters differ";
  }
}

AOEVAL_INSTANTIATE_OVER_REGISTRY(Conformance);

}  // namespace
}  // namespace aoeval
