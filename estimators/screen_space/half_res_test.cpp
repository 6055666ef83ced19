// Half resolution (half_res.h) for hbao-split and gtao: the half frame's geometry (every sample
// rebuilt at its full-resolution eye position), an open plane that stays at its full-resolution
// AO, a constructed G-buffer whose depth step and crease the joint bilateral upsample does not
// bleed across, the fallback where no sample fits, the parameter in both tables, and, where a
// Vulkan device exists, the twins' agreement at half resolution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "estimators/gtao/gtao.h"
#include "estimators/gtao/gtao_vulkan.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/registry.h"
#include "estimators/screen_space/half_res.h"
#include "estimators/testing/ssao_test_scenes.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/corpus.h"

namespace aoeval {
namespace {

ParamSet params_of(const std::string& name, const nlohmann::json& overrides) {
  const EstimatorInfo& info = find_estimator(name);
  return resolve_params(info.name, info.params, overrides, "test");
}

// Half pixel (i, j) seen through the half frame's principal point and focal length is full pixel
// (2i, 2j) seen through the full frame's: the same view ray, so the same eye position.
TEST(HalfResolution, HalfFrameRebuildsEverySampleWhereItIs) {
  for (int w : {9, 10}) {
    ScreenSpaceFrame full;
    full.width = w;
    full.height = w + 3;
    full.focal = 7.5f;
    const ScreenSpaceFrame half = half_resolution_shape(full);
    EXPECT_EQ(half.width, (w + 1) / 2);
    EXPECT_EQ(half.height, (w + 4) / 2);
    EXPECT_EQ(half.focal, 3.75f);
    const double cx = 0.5 * half.width + half.centre_shift.x;
    const double cy = 0.5 * half.height + half.centre_shift.y;
    for (int i = 0; i < half.width; ++i) {
      EXPECT_DOUBLE_EQ((i + 0.5 - cx) / half.focal, (2 * i + 0.5 - 0.5 * full.width) / full.focal);
      EXPECT_DOUBLE_EQ((i + 0.5 - cy) / half.focal, (2 * i + 0.5 - 0.5 * full.height) / full.focal);
    }
  }
}

// An open plane occludes nothing at either resolution: gtao's AO is 1 and hbao-split's stays at its
// full-resolution value (both within rounding) on the floor up to 60 degrees from its normal.
TEST(HalfResolution, OpenPlaneStaysAtTheFullResolutionValue) {
  const TestView view = grazing_floor(161, 120);  // an odd width: a clamped last column
  const ScreenSpaceFrame frame = screen_space_frame_from_gbuffer(view.gbuffer);
  const GtaoOutput g_full =
      gtao_cpu(frame, view.gbuffer.camera, gtao_settings_of(params_of("gtao-cpu", {{"R", 1.0}})));
  const GtaoOutput g_half =
      gtao_cpu(frame, view.gbuffer.camera,
               gtao_settings_of(params_of("gtao-cpu", {{"R", 1.0}, {"resolution", "half"}})));
  const HbaoCpuResult h_full =
      hbao_split_cpu(frame, hbao_settings_of(params_of("hbao-split-cpu", {})));
  const HbaoCpuResult h_half = hbao_split_cpu(
      frame, hbao_settings_of(params_of("hbao-split-cpu", {{"resolution", "half"}})));
  ASSERT_EQ(g_half.ao.size(), frame.depth.size());
  ASSERT_EQ(h_half.ao.size(), frame.depth.size());
  EXPECT_EQ(g_half.raw_ao.size(), static_cast<size_t>(81 * 60));
  double gtao_diff = 0.0, hbao_diff = 0.0, min_half = 1.0;
  size_t count = 0;
  for (int j = 0; j < view.gbuffer.height; ++j) {
    for (int i = 0; i < view.gbuffer.width; ++i) {
      const size_t k = view.gbuffer.index(i, j);
      if (!view.gbuffer.covered(k) || view_angle_deg(view.gbuffer, i, j) > 60.0) continue;
      gtao_diff = std::max(gtao_diff, std::abs(static_cast<double>(g_half.ao[k]) - g_full.ao[k]));
      hbao_diff = std::max(hbao_diff, std::abs(static_cast<double>(h_half.ao[k]) - h_full.ao[k]));
      min_half = std::min(min_half, static_cast<double>(g_half.ao[k]));
      ++count;
    }
  }
  std::printf("open plane, %zu pixels: max |half - full| gtao %.3g, hbao-split %.3g\n", count,
              gtao_diff, hbao_diff);
  ASSERT_GT(count, 2000u);
  EXPECT_GT(min_half, 0.9999);
  EXPECT_LT(gtao_diff, 1e-4);
  EXPECT_LT(hbao_diff, 1e-3);
  EXPECT_GT(g_half.pass_ms.count("upsample_ms"), 0u);
}

// A constructed 9 x 6 G-buffer facing the camera: columns 0-4 at depth 1, columns 5-8 at depth 2
// (a step between columns 4 and 5). The half frame keeps columns 0, 2, 4 (depth 1) and 6, 8
// (depth 2); give them AO 0.3 and 0.9. A plain bilinear upsample would give column 5 the mean 0.6;
// the joint bilateral one gives every near pixel 0.3 and every far pixel 0.9, within rounding.
ScreenSpaceFrame step_frame() {
  ScreenSpaceFrame f;
  f.width = 9;
  f.height = 6;
  f.focal = 10.0f;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 9; ++i) {
      f.depth.push_back(i < 5 ? 1.0f : 2.0f);
      f.normal.emplace_back(0.0f, 0.0f, -1.0f);
    }
  return f;
}

TEST(HalfResolution, UpsampleDoesNotBleedAcrossADepthStep) {
  const ScreenSpaceFrame f = step_frame();
  const ScreenSpaceFrame low = half_resolution_frame(f);
  ASSERT_EQ(low.width, 5);
  ASSERT_EQ(low.height, 3);
  std::vector<float> ao(low.depth.size());
  for (size_t k = 0; k < ao.size(); ++k) ao[k] = low.depth[k] == 1.0f ? 0.3f : 0.9f;
  const std::vector<float> up = upsample_half_res(f, ao);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 9; ++i)
      EXPECT_NEAR(up[static_cast<size_t>(j * 9 + i)], i < 5 ? 0.3f : 0.9f, 1e-6) << i << "," << j;
}

// A crease at equal depth: columns 5-8 turn their normal 90 degrees (a wall meeting the floor);
// the normal weight (n_p . n_k)^8 = 0 keeps each side's value, and the vectors (bent normals)
// follow the same weights.
TEST(HalfResolution, UpsampleDoesNotBleedAcrossACrease) {
  ScreenSpaceFrame f = step_frame();
  for (size_t k = 0; k < f.depth.size(); ++k) {
    f.depth[k] = 1.0f;
    if (k % 9 >= 5) f.normal[k] = glm::vec3(1.0f, 0.0f, 0.0f);
  }
  const ScreenSpaceFrame low = half_resolution_frame(f);
  std::vector<float> ao(low.depth.size());
  std::vector<glm::vec3> v(low.depth.size());
  for (size_t k = 0; k < ao.size(); ++k) {
    const bool wall = low.normal[k].x > 0.5f;
    ao[k] = wall ? 0.9f : 0.3f;
    v[k] = wall ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  }
  const std::vector<float> up = upsample_half_res(f, ao);
  const std::vector<glm::vec3> upv = upsample_half_res(f, v);
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(up[static_cast<size_t>(9 + i)], i < 5 ? 0.3f : 0.9f, 1e-6) << i;
    EXPECT_NEAR(upv[static_cast<size_t>(9 + i)].y, i < 5 ? 0.0f : 1.0f, 1e-6) << i;
  }
}

// Where every candidate is rejected (a pixel on a feature the half frame missed), the candidate
// nearest in depth alone gives the value; with no covered candidate, AO is 1 and the vector 0;
// uncovered pixels stay 0.
TEST(HalfResolution, FallbackWhereNoSampleFits) {
  ScreenSpaceFrame f = step_frame();
  f.depth.assign(f.depth.size(), 0.0f);
  for (int j = 0; j < 6; ++j) f.depth[static_cast<size_t>(j * 9 + 4)] = 1.0f;  // kept column 4
  f.depth[9 + 3] = 3.0f;  // (3, 1): candidates (2, *) are background, (4, *) at depth 1
  f.depth[9 + 1] = 5.0f;  // (1, 1): candidates columns 0 and 2, all background
  f.depth[2 * 9 + 4] = 1.0f;
  const ScreenSpaceFrame low = half_resolution_frame(f);
  std::vector<float> ao(low.depth.size(), 0.5f);
  ao[static_cast<size_t>(0 * 5 + 2)] = 0.25f;  // half (2, 0) = full (4, 0), depth 1
  ao[static_cast<size_t>(1 * 5 + 2)] = 0.75f;  // half (2, 1) = full (4, 2), depth 1
  const std::vector<float> up = upsample_half_res(f, ao);
  EXPECT_FLOAT_EQ(up[9 + 3], 0.25f);  // both (4, 0) and (4, 2) are 2 off in depth: the first
  EXPECT_FLOAT_EQ(up[9 + 1], 1.0f);
  EXPECT_FLOAT_EQ(up[0], 0.0f);
}

TEST(HalfResolution, DeclaredInBothTablesOfBothEstimators) {
  for (const char* name : {"gtao", "gtao-cpu", "hbao-split", "hbao-split-cpu"}) {
    EXPECT_EQ(params_of(name, {}).choice("resolution"), "full") << name;
    EXPECT_THROW(params_of(name, {{"resolution", "quarter"}}), InputError) << name;
  }
}

// ---- Vulkan twins at half resolution: skipped with the reason where there is no device.
#define REQUIRE_VULKAN(vk)                                      \
  std::string skip_reason;                                      \
  vk::Context* vk = vk::shared_context(&skip_reason);           \
  if (!vk) GTEST_SKIP() << "no Vulkan device: " << skip_reason; \
  RecordProperty("vulkan_device", vk->device_description());

// The same kernels and the same upsample text on both sides, the same bits in: bit-identical on
// lavapipe, within the full-resolution tests' tolerances elsewhere (1e-4 gtao, 1e-3 hbao-split).
TEST(HalfResolutionVulkan, TwinsAgreeAtHalfResolution) {
  REQUIRE_VULKAN(vk);
  const Scene scene = load_scene("bunny");
  const Camera camera = make_camera(scene.views.front(), 161, 121);
  EmbreeScene embree(scene);
  const ScreenSpaceFrame frame = screen_space_frame_from_gbuffer(render_gbuffer(embree, camera));
  const bool lavapipe = vk->device_description().find("llvmpipe") != std::string::npos;
  const GtaoSettings gs = gtao_settings_of(params_of("gtao-cpu", {{"resolution", "half"}}));
  const GtaoOutput gc = gtao_cpu(frame, camera, gs);
  GtaoDevice gd(*vk, gs, frame, camera);
  const GtaoOutput gg = gd.run();
  const double gdiff = hbao_max_abs_difference(frame, gc.ao, gg.ao);
  double bent = 0.0;
  for (size_t k = 0; k < frame.depth.size(); ++k)
    if (frame.depth[k] > 0.0f)
      bent = std::max(bent, static_cast<double>(glm::length(gc.bent[k] - gg.bent[k])));
  const HbaoSettings hs = hbao_settings_of(params_of("hbao-split-cpu", {{"resolution", "half"}}));
  const HbaoCpuResult hc = hbao_split_cpu(frame, hs);
  HbaoDevice hd(*vk, hs, frame, camera);
  const HbaoGpuResult hg = hd.run();
  const double hdiff = hbao_max_abs_difference(frame, hc.ao, hg.ao);
  std::printf("half-resolution twins: gtao AO %.3g bent %.3g, hbao-split AO %.3g (horizon %.3g)\n",
              gdiff, bent, hdiff, hbao_max_abs_difference(frame, hc.horizon_ao, hg.horizon_ao));
  EXPECT_LE(gdiff, lavapipe ? 0.0 : 1e-4);
  EXPECT_LE(bent, lavapipe ? 0.0 : 1e-4);
  EXPECT_LE(hdiff, 1e-3);
  EXPECT_LE(hbao_max_abs_difference(frame, hc.horizon_ao, hg.horizon_ao), 1e-3);
  for (const auto* ms : {&gg.pass_ms, &hg.pass_ms}) {
    EXPECT_GT(ms->count("downsample_ms"), 0u);
    EXPECT_GT(ms->count("upsample_ms"), 0u);
  }
}

}  // namespace
}  // namespace aoeval
