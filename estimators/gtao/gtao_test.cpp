// gtao-cpu (and, where a Vulkan device exists, gtao): an open floor seen up to 80 degrees from its
// normal (AO = 1, bent normal = the normal), the closed-form crease, determinism, the parameter
// table, and the twins' agreement on the same G-buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "base/errors.h"
#include "estimators/gtao/gtao.h"
#include "estimators/gtao/gtao_vulkan.h"
#include "estimators/registry.h"
#include "estimators/testing/ssao_test_scenes.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/corpus.h"

namespace aoeval {
namespace {

GtaoSettings settings_with(nlohmann::json overrides) {
  const EstimatorInfo& info = find_estimator("gtao-cpu");
  return gtao_settings_of(resolve_params(info.name, info.params, overrides, "test"));
}

GtaoOutput run_cpu(const TestView& view, const GtaoSettings& s) {
  return gtao_cpu(screen_space_frame_from_gbuffer(view.gbuffer), view.gbuffer.camera, s);
}

double angle_deg(glm::vec3 a, glm::vec3 b) {
  const double c = std::clamp(static_cast<double>(glm::dot(a, b)), -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

// An open plane occludes nothing. Every sample of the floor is rebuilt on the plane itself (1/z
// interpolated bilinearly is exact on a plane, gtao_kernel.glsl), so every horizon stays at the
// tangent plane up to rounding, where the integrand cos(theta - gamma) vanishes: the AO is 1 and
// the bent normal, sum over evenly spaced slices of (4/3 (n . d) d + 2/3 (n . v) v), is the normal
// (the slices' d d^T sum to slices/2 (I - v v^T)), up to float rounding, at every view angle up to
// 80 degrees, with and without denoise, for 1 to 8 slices.
TEST(GtaoCpu, OpenPlaneIsUnoccludedUpTo80Degrees) {
  const TestView view = grazing_floor(160, 120);
  for (int slices : {1, 2, 3, 8}) {
    for (bool denoise : {false, true}) {
      const GtaoOutput r =
          run_cpu(view, settings_with({{"slices", slices}, {"denoise", denoise}, {"R", 1.0}}));
      double min_ao = 1.0, max_angle = 0.0, sum_ao = 0.0;
      size_t count = 0;
      for (int j = 0; j < view.gbuffer.height; ++j) {
        for (int i = 0; i < view.gbuffer.width; ++i) {
          const size_t k = view.gbuffer.index(i, j);
          if (!view.gbuffer.covered(k) || view_angle_deg(view.gbuffer, i, j) > 80.0) continue;
          min_ao = std::min(min_ao, static_cast<double>(r.ao[k]));
          sum_ao += r.ao[k];
          if (slices >= 2) max_angle = std::max(max_angle, angle_deg(r.bent[k], {0, 1, 0}));
          ++count;
        }
      }
      std::printf(
          "open floor, %d slices, denoise %d: %zu pixels, min AO %.7f, mean %.7f, max "
          "bent angle %.4f deg\n",
          slices, denoise, count, min_ao, sum_ao / static_cast<double>(count), max_angle);
      ASSERT_GT(count, 10000u);
      EXPECT_GT(min_ao, 0.9999);
      EXPECT_LT(max_angle, 0.05);
    }
  }
}

// The crease (floor meeting a wall taller than R, ssao_test_scenes.h): with exact horizons and
// falloff 0 the slice integral is exact wherever each slice's occluded set is the arc below its
// horizon, which holds for the crease's wall as far as the slice sees it (it rises from the
// floor), so the error comes from the discretisation: 16 jittered slices (a Riemann sum over phi
// of a function with kinks) and 32 samples per side, whose screen spacing can miss the top of the
// wall within R by up to one sample.
TEST(GtaoCpu, CreaseMatchesTheClosedForm) {
  const TestView view = crease(160, 120);
  const double radius = 0.5;
  const std::vector<CreasePixel> pixels = crease_floor_pixels(view.gbuffer, radius + 0.05);
  const GtaoOutput r = run_cpu(
      view, settings_with({{"R", radius}, {"slices", 16}, {"steps", 32}, {"denoise", false}}));
  const CreaseErrors e = crease_errors(r.ao, pixels, radius, false);
  std::printf("crease: %zu pixels (%zu within R), bias %.4f, mean abs %.4f, max abs %.4f\n",
              pixels.size(), e.within_radius, e.bias, e.mean_abs, e.max_abs);
  ASSERT_GT(e.within_radius, 1000u);
  EXPECT_LT(std::abs(e.bias), 0.01);
  EXPECT_LT(e.mean_abs, 0.015);
  EXPECT_LT(e.max_abs, 0.08);
}

// The falloff fades a sample's horizon towards the tangent plane and the thickness heuristic pulls
// the horizon down after lower samples: both can only lower a horizon, and the slice integral
// grows as a horizon falls, so neither may darken any pixel (without denoise, pixel by pixel).
TEST(GtaoCpu, FalloffAndThicknessOnlyRemoveOcclusion) {
  const TestView view = crease(80, 60);
  const nlohmann::json base = {{"R", 0.5}, {"denoise", false}};
  const GtaoOutput plain = run_cpu(view, settings_with(base));
  for (const char* key : {"falloff", "thickness"}) {
    nlohmann::json o = base;
    o[key] = 0.5;
    const GtaoOutput r = run_cpu(view, settings_with(o));
    double gain = 0.0;
    for (size_t k = 0; k < r.ao.size(); ++k) {
      EXPECT_GE(r.ao[k], plain.ao[k] - 1e-6f) << key << " at pixel " << k;
      gain += r.ao[k] - plain.ao[k];
    }
    EXPECT_GT(gain, 1.0) << key << " changed nothing";
  }
}

TEST(GtaoCpu, SameSeedSameBitsOtherSeedOtherBits) {
  const TestView view = crease(80, 60);
  const GtaoOutput a = run_cpu(view, settings_with({{"seed", 3}}));
  const GtaoOutput b = run_cpu(view, settings_with({{"seed", 3}}));
  const GtaoOutput c = run_cpu(view, settings_with({{"seed", 4}}));
  EXPECT_EQ(a.ao, b.ao);
  EXPECT_EQ(a.bent, b.bent);
  EXPECT_NE(a.ao, c.ao);
  // Without jitter the seed is irrelevant.
  EXPECT_EQ(run_cpu(view, settings_with({{"seed", 3}, {"jitter", false}})).ao,
            run_cpu(view, settings_with({{"seed", 4}, {"jitter", false}})).ao);
}

// Without bent normals the estimate carries AO only; the final power is applied last.
TEST(GtaoCpu, ChannelsAndFinalPower) {
  const TestView view = crease(80, 60);
  const GtaoSettings plain = settings_with({});
  const GtaoSettings squared = settings_with({{"final_power", 2.0}, {"bent", false}});
  const GtaoOutput a = run_cpu(view, plain);
  const GtaoOutput b = run_cpu(view, squared);
  EXPECT_TRUE(b.bent.empty());
  for (size_t k = 0; k < a.ao.size(); ++k)
    EXPECT_EQ(b.ao[k], static_cast<float>(std::pow(static_cast<double>(a.ao[k]), 2.0)));
  const EstimateResult with = gtao_estimate_result(plain, a);
  EXPECT_EQ(with.extra_channels.count("bent.X"), 1u);
  EXPECT_EQ(gtao_estimate_result(squared, b).extra_channels.count("bent.X"), 0u);
}

TEST(GtaoCpu, DeclaresItsDefinition) {
  const EstimatorInfo& info = find_estimator("gtao-cpu");
  const ParamSet p = resolve_params(info.name, info.params, nlohmann::json::object(), "test");
  const AoDefinition d = info.definition(p);
  EXPECT_EQ(d.weighting, Weighting::cosine);
  EXPECT_EQ(d.dmax, p.real("R"));
  EXPECT_EQ(d.falloff, Falloff::none);
  EXPECT_EQ(
      info.definition(resolve_params(info.name, info.params, {{"falloff", 0.5}}, "t")).falloff,
      Falloff::linear);
  EXPECT_THROW(resolve_params(info.name, info.params, {{"slices", 0}}, "--set"), InputError);
  EXPECT_THROW(resolve_params(info.name, info.params, {{"radius", 1}}, "--set"), InputError);
  EXPECT_THROW(gtao_cpu(ScreenSpaceFrame{1, 1, 1.0f, {1.0f}, {glm::vec3(0, 0, -1)}}, Camera{},
                        gtao_settings_of(p)),
               InputError);
}

// ---- gtao (Vulkan): skipped with the reason where there is no device; lavapipe runs them.

#define REQUIRE_VULKAN(vk)                                      \
  std::string skip_reason;                                      \
  vk::Context* vk = vk::shared_context(&skip_reason);           \
  if (!vk) GTEST_SKIP() << "no Vulkan device: " << skip_reason; \
  RecordProperty("vulkan_device", vk->device_description());

double max_abs_difference(const ScreenSpaceFrame& f, const std::vector<float>& a,
                          const std::vector<float>& b) {
  double m = 0.0;
  for (size_t k = 0; k < f.depth.size(); ++k)
    if (f.depth[k] > 0.0f) m = std::max(m, std::abs(static_cast<double>(a[k]) - b[k]));
  return m;
}

double max_bent_difference(const ScreenSpaceFrame& f, const std::vector<glm::vec3>& a,
                           const std::vector<glm::vec3>& b) {
  double m = 0.0;
  for (size_t k = 0; k < f.depth.size(); ++k)
    if (f.depth[k] > 0.0f) m = std::max(m, static_cast<double>(glm::length(a[k] - b[k])));
  return m;
}

// The twins compile one kernel source that uses + - * / and sqrt only, and read the same bits
// (depth, eye-space normals, noise, step and slice tables); both finish on the host with one
// function. A device that rounds those operations as IEEE 754 does (lavapipe) therefore gives the
// CPU's bits; the test demands 1e-4 (a flipped comparison at a texel boundary of the bilinear
// fetch would show up here) and prints the measured difference.
TEST(GtaoVulkan, TwinsAgreeOnTheSameGBuffer) {
  REQUIRE_VULKAN(vk);
  const Scene scene = load_scene("bunny");
  const Camera camera = make_camera(scene.views.front(), 160, 120);
  EmbreeScene embree(scene);
  const ScreenSpaceFrame frame = screen_space_frame_from_gbuffer(render_gbuffer(embree, camera));
  for (bool denoise : {false, true}) {
    const GtaoSettings s = settings_with({{"denoise", denoise}, {"slices", denoise ? 3 : 4}});
    const GtaoOutput cpu = gtao_cpu(frame, camera, s);
    GtaoDevice device(*vk, s, frame, camera);
    const GtaoOutput gpu = device.run();
    const double diff = max_abs_difference(frame, cpu.ao, gpu.ao);
    const double bent = max_bent_difference(frame, cpu.bent, gpu.bent);
    size_t differing = 0;
    for (size_t k = 0; k < cpu.ao.size(); ++k) differing += cpu.ao[k] != gpu.ao[k] ? 1 : 0;
    std::printf(
        "twins, denoise %d: max |cpu - gpu| AO %.3g (raw %.3g), bent %.3g, %zu pixels "
        "not bit-identical\n",
        denoise, diff, max_abs_difference(frame, cpu.raw_ao, gpu.raw_ao), bent, differing);
    EXPECT_LE(diff, 1e-4);
    EXPECT_LE(bent, 1e-4);
    // lavapipe (llvmpipe) compiles + - * / and sqrt to the CPU's IEEE instructions: every bit.
    if (vk->device_description().find("llvmpipe") != std::string::npos) {
      EXPECT_EQ(differing, 0u);
    }
    EXPECT_GT(gpu.pass_ms.count("horizon_ms"), 0u);
    EXPECT_EQ(gpu.pass_ms.count("denoise_ms"), denoise ? 1u : 0u);
    EXPECT_EQ(gpu.pass_ms.count("geometry_ms"), 0u);
  }
}

// gbuffer=raster: the device rasterises the scene and converts its normals with the shared
// eye_normal.glsl; the CPU twin on the downloaded raster G-buffer agrees as on the Embree one.
TEST(GtaoVulkan, RasterGBufferFeedsTheSameKernel) {
  REQUIRE_VULKAN(vk);
  const Scene scene = load_scene("bunny");
  const Camera camera = make_camera(scene.views.front(), 160, 120);
  const GtaoSettings s = settings_with({});
  GtaoDevice device(*vk, s, scene, camera);
  const GtaoOutput gpu = device.run();
  EXPECT_GT(gpu.pass_ms.count("geometry_ms"), 0u);
  EXPECT_GT(gpu.pass_ms.count("total_ms"), 0u);
  const ScreenSpaceFrame raster = device.frame();
  const GtaoOutput cpu = gtao_cpu(raster, camera, s);
  EXPECT_LE(max_abs_difference(raster, cpu.ao, gpu.ao), 1e-4);
  EXPECT_LE(max_bent_difference(raster, cpu.bent, gpu.bent), 1e-4);
}

TEST(GtaoVulkan, OpenPlaneOnTheDevice) {
  REQUIRE_VULKAN(vk);
  const TestView view = grazing_floor(160, 120);
  GtaoDevice device(*vk, settings_with({{"R", 1.0}}), screen_space_frame_from_gbuffer(view.gbuffer),
                    view.gbuffer.camera);
  const GtaoOutput r = device.run();
  double min_ao = 1.0;
  for (int j = 0; j < view.gbuffer.height; ++j)
    for (int i = 0; i < view.gbuffer.width; ++i) {
      const size_t k = view.gbuffer.index(i, j);
      if (view.gbuffer.covered(k) && view_angle_deg(view.gbuffer, i, j) <= 80.0)
        min_ao = std::min(min_ao, static_cast<double>(r.ao[k]));
    }
  EXPECT_GT(min_ao, 0.9999);
}

TEST(GtaoVulkan, RegisteredWithTheGBufferChoice) {
  const EstimatorInfo& info = find_estimator("gtao");
  EXPECT_EQ(info.backend, Backend::vulkan);
  const ParamSet p = resolve_params(info.name, info.params, nlohmann::json::object(), "test");
  EXPECT_EQ(p.choice("gbuffer"), "raster");
  EXPECT_THROW(resolve_params(info.name, info.params, parse_set_arguments({"gbuffer=gl"}), "--set"),
               InputError);
  // The twins declare the same parameters (gtao adds gbuffer only).
  EXPECT_EQ(info.params.size(), find_estimator("gtao-cpu").params.size() + 1);
}

}  // namespace
}  // namespace aoeval
