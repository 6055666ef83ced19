// hbao-split over time (CONTRACT §10): the per-pixel random rotation of §4.1.2 advances every frame
// (frame k's texture from seed + k, the seed rule), in both twins; the still frame is the still
// estimate bit for bit.
#include <gtest/gtest.h>

#include "estimators/hbao_split/hbao_split.h"
#include "estimators/hbao_split/hbao_vulkan.h"
#include "estimators/testing/static_frames.h"
#include "estimators/vulkan/vk_context.h"
#include "scenes/corpus.h"

namespace aoeval {
namespace {

HbaoSettings settings_with(const nlohmann::json& overrides, uint64_t frame = 0) {
  return settings_at_frame("hbao-split-cpu", hbao_settings_of, overrides, frame);
}

// Frame k is the still estimate with seed + k (what the runner gave every built-in before it kept
// state: a fresh instance of seed + k), so sequences at the defaults are unchanged too; one seed
// for every frame repeats frame 0.
TEST(HbaoSplitTemporal, FrameKRotatesByTheTextureOfSeedPlusK) {
  const TestView view = crease(64, 48);
  const auto frames = run_static_frames("hbao-split-cpu", {{"seed", 5}}, view, 3);
  const auto kept = run_static_frames("hbao-split-cpu", {{"seed", 5}}, view, 3, false);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(frames[k], run_still_frame("hbao-split-cpu", {{"seed", 5 + k}}, view).ao) << k;
    EXPECT_EQ(frames[k], hbao_split_cpu(screen_space_frame_from_gbuffer(view.gbuffer),
                                        settings_with({{"seed", 5}}, static_cast<uint64_t>(k)))
                             .ao)
        << k;
    EXPECT_EQ(kept[k], frames[0]) << k;
  }
  EXPECT_NE(frames[1], frames[0]);
  EXPECT_EQ(hbao_random_texture(settings_with({{"seed", 5}}, 2)),
            hbao_random_texture(settings_with({{"seed", 7}})));
}

// A still view and frame 0 of a sequence are the still estimate bit for bit, and the row records
// nothing new (hbao-split has no time parameter: its texture per frame is the seed rule's).
TEST(HbaoSplitTemporal, StillFrameUnchanged) {
  const TestView view = crease(64, 48);
  const std::vector<float> plain =
      hbao_split_cpu(screen_space_frame_from_gbuffer(view.gbuffer), settings_with({})).ao;
  nlohmann::json derived;
  EXPECT_EQ(run_still_frame("hbao-split-cpu", {}, view, &derived).ao, plain);
  EXPECT_TRUE(derived.empty()) << derived.dump();
  EXPECT_EQ(run_static_frames("hbao-split-cpu", {}, view, 1).front(), plain);
}

// `temporal` (declared once in hbao_param_specs with the stage's fragment) runs the frames through
// the shared temporal stage: over a still camera (no motion, nothing disoccluded) with alpha_min 0
// and a 16-frame history, without the clamp and the anti-lag, frame k is the running mean of the
// plain frames 0..k (seed + k each), and frame 0 is the plain estimate bit for bit. The mean of 6
// rotated textures is smoother than one.
TEST(HbaoSplitTemporal, TheTemporalStageAveragesTheRotatedFrames) {
  const TestView view = crease(64, 48);
  const auto plain = run_static_frames("hbao-split-cpu", {{"seed", 5}}, view, 6);
  const auto accumulated = run_static_frames(
      "hbao-split-cpu", {{"seed", 5}, {"temporal", true}, {"clamp", false}, {"antilag", 0}}, view,
      6);
  EXPECT_EQ(accumulated[0], plain[0]);
  for (int k = 1; k < 6; ++k)
    for (size_t p = 0; p < view.gbuffer.pixel_count(); ++p) {
      if (!view.gbuffer.covered(p)) continue;
      double mean = 0.0;
      for (int j = 0; j <= k; ++j) mean += plain[j][p] / (k + 1.0);
      ASSERT_NEAR(accumulated[k][p], mean, 1e-5) << "frame " << k << ", pixel " << p;
    }
  EXPECT_EQ(find_estimator("hbao-split-cpu").find_param("temporal")->default_value, false);
  EXPECT_EQ(find_estimator("hbao-split").find_param("history_read")->default_value, "catmull-rom");
}

// The twins at frame k > 0 read the same random texture (seed + k) and agree as on the still frame
// (hbao_split_test.cpp's 1e-3).
TEST(HbaoSplitTemporal, TwinsAgreeAtFrameK) {
  std::string skip_reason;
  vk::Context* vk = vk::shared_context(&skip_reason);
  if (!vk) GTEST_SKIP() << "no Vulkan device: " << skip_reason;
  const Scene scene = load_scene("bunny");
  const Camera camera = make_camera(scene.views.front(), 160, 120);
  EmbreeScene embree(scene);
  const ScreenSpaceFrame frame = screen_space_frame_from_gbuffer(render_gbuffer(embree, camera));
  const HbaoSettings s = settings_with({}, 9);
  const HbaoCpuResult cpu = hbao_split_cpu(frame, s);
  HbaoDevice device(*vk, s, frame, camera);
  const double diff = hbao_max_abs_difference(frame, cpu.ao, device.run().ao);
  std::printf("twins at frame 9: max |cpu - gpu| = %.3g\n", diff);
  EXPECT_LE(diff, 1e-3);
  EXPECT_NE(cpu.ao, hbao_split_cpu(frame, settings_with({})).ao);
}

}  // namespace
}  // namespace aoeval
