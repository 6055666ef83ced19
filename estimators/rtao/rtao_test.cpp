// rtao on analytic scenes with known answers: its rays are a per-pixel low-discrepancy sequence
// that advances frame by frame, so at the foot of a wall (AO = 1/2 exactly: the wall holds half
// the cosine measure) 2^n frames of 1 ray accumulate to exactly 1/2; its still frames repeat and
// say they are still; and the denoiser keeps an open plane at 1.
#include "estimators/rtao/rtao.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>

#include "estimators/raytraced/raytraced.h"
#include "scenes/analytic_scenes.h"

namespace aoeval {
namespace {

Scene wall_foot() {
  SceneObject floor = generated("floor", "plane", {{"size", {40, 40}}});
  SceneObject wall = generated("wall", "box", {{"size", {2, 40, 40}}}, {-1.0f, 0, 0});
  return scene_of({std::move(floor), std::move(wall)});
}

std::unique_ptr<Estimator> make(const nlohmann::json& overrides) {
  const EstimatorInfo e = rtao_estimator();
  return e.create(resolve_params(e.name, e.params, overrides, "test"));
}

// The floor at x = 1e-3 beside the wall, probed by 64 pixels (each its own scramble). A pixel's
// first 2^n rays form a (0, n, 2)-net (samplers.h), which puts exactly half its points in
// u.x < 1/2; the concentric map sends those to local x < 0 (the sign of x_disk is the sign of 2
// u.x - 1 on every wedge), and the frame of n = +Y has local x = world x: exactly half the rays
// hit the wall. So the running mean (alpha_min 0, no clamp, no anti-lag, no filter) is 1/2 after
// 2, 4, 8, 16 frames, where independent rays would leave a standard error of 0.5/sqrt(16) = 0.125.
TEST(Rtao, TheAdvancingSequenceIntegratesTheFootOfAWallExactly) {
  const Scene s = wall_foot();
  EmbreeScene es(s);
  const GBuffer g = probe({1e-3f, 0, 0}, {0, 1, 0}, 64);
  auto est = make({{"alpha_min", 0.0},
                   {"history_limit", 64},
                   {"clamp", false},
                   {"antilag", 0.0},
                   {"atrous_iterations", 0}});
  for (int k = 0; k < 16; ++k) {
    const FrameInfo info{
        .index = k, .count = 16, .fps = 30, .seed_offset = static_cast<uint64_t>(k)};
    est->prepare({s, es, g, &info});
    const EstimateResult r = est->run({s, es, g, &info});
    for (float raw : r.extra_channels.at("AO_raw")) ASSERT_TRUE(raw == 0.0f || raw == 1.0f);
    if (((k + 1) & k) == 0 && k > 0) {  // k + 1 = 2, 4, 8, 16 frames
      for (float a : r.ao) EXPECT_NEAR(a, 0.5f, 1e-6) << "after " << k + 1 << " frames";
    }
    EXPECT_EQ(r.extra_channels.at("history_length")[0], static_cast<float>(k + 1));
    for (const char* pass : {"rays_ms", "temporal_ms", "variance_ms", "atrous_ms"})
      EXPECT_EQ(r.pass_ms.count(pass), 1u) << pass;
  }
}

// With "seed_per_frame": false every frame has seed_offset 0: the same rays, so the running mean
// never moves from the first frame's 0/1 values.
TEST(Rtao, OneSeedForEveryFrameTracesTheSameRays) {
  const Scene s = wall_foot();
  EmbreeScene es(s);
  const GBuffer g = probe({1e-3f, 0, 0}, {0, 1, 0}, 64);
  auto est = make({{"alpha_min", 0.0}, {"clamp", false}, {"atrous_iterations", 0}});
  std::vector<float> first;
  for (int k = 0; k < 8; ++k) {
    const FrameInfo info{.index = k, .count = 8, .fps = 30, .seed_offset = 0};
    const EstimateResult r = est->run({s, es, g, &info});
    if (k == 0) first = r.ao;
    EXPECT_EQ(r.ao, first) << k;
  }
}

// A still view runs as frame 0: the same bits every run (no history carried between them), and
// derived() says it is a still frame; a sequence's frames do not.
TEST(Rtao, AStillViewIsFrameZeroAndSaysSo) {
  const Scene s = wall_foot();
  EmbreeScene es(s);
  const GBuffer g = probe({0.3f, 0, 0.1f}, {0, 1, 0}, 64);
  auto est = make(nlohmann::json::object());
  est->prepare({s, es, g});
  const auto a = est->run({s, es, g}).ao, b = est->run({s, es, g}).ao;
  EXPECT_EQ(a, b);
  EXPECT_TRUE(est->derived().contains("still_frame"));
  const FrameInfo info{.index = 0, .count = 4, .fps = 30, .seed_offset = 0};
  est->prepare({s, es, g, &info});
  EXPECT_EQ(est->run({s, es, g, &info}).ao, a);  // frame 0 of a sequence is the still frame
  EXPECT_FALSE(est->derived().contains("still_frame"));
  auto other = make({{"seed", 8}});
  EXPECT_NE(other->run({s, es, g}).ao, a);
}

// An open plane stays at exactly 1 through every stage (each ray escapes; the filters average
// ones), and a closed box's inside at 0.
TEST(Rtao, OpenPlaneIsOneAndABoxInteriorIsZero) {
  const Scene plane = scene_of({generated("floor", "plane", {{"size", {50, 50}}})});
  Scene scene = plane;
  scene.views.front().eye = {0, 1, 1.5f};
  EmbreeScene es(scene);
  const GBuffer g = render_gbuffer(es, make_camera(scene.views.front(), 24, 18));
  auto est = make({{"rays", 4}});
  for (int k = 0; k < 3; ++k) {
    const FrameInfo info{
        .index = k, .count = 3, .fps = 30, .seed_offset = static_cast<uint64_t>(k)};
    const EstimateResult r = est->run({scene, es, g, &info});
    for (size_t p = 0; p < g.pixel_count(); ++p) {
      if (g.covered(p)) {
        EXPECT_NEAR(r.ao[p], 1.0f, 1e-6f);
      }
    }
  }
  const Scene box = scene_of({generated("box", "box", {{"size", {2, 2, 2}}, {"inward", true}})});
  EmbreeScene box_es(box);
  for (float a :
       make(nlohmann::json::object())->run({box, box_es, probe({0.3f, 0, 0.2f}, {0, 1, 0}, 16)}).ao)
    EXPECT_EQ(a, 0.0f);
}

// The whole denoiser (the temporal stage, the variance, five a-trous passes) gives the same bits on
// one thread as on eight, frame after frame: every parallel loop sums each pixel's taps in one
// order whatever the tiling.
TEST(Rtao, OneThreadGivesTheBitsOfMany) {
  const Scene s = wall_foot();
  Scene scene = s;
  scene.views.front().eye = {2.0f, 1.5f, 2.5f};
  scene.views.front().target = {-1.0f, 0.2f, 0.0f};
  EmbreeScene es(scene);
  const GBuffer g = render_gbuffer(es, make_camera(scene.views.front(), 61, 45));
  auto frames = [&](int threads) {
    std::vector<std::vector<float>> out;
    tbb::task_arena(threads).execute([&] {
      auto est = make({{"rays", 2}, {"t_max", 1.5}});
      for (int k = 0; k < 6; ++k) {
        const FrameInfo info{
            .index = k, .count = 6, .fps = 30, .seed_offset = static_cast<uint64_t>(k)};
        EstimateResult r = est->run({scene, es, g, &info});
        out.push_back(std::move(r.ao));
        out.push_back(std::move(r.extra_channels.at("AO_variance")));
      }
    });
    return out;
  };
  const tbb::global_control most(tbb::global_control::max_allowed_parallelism, 8);
  const auto one = frames(1), many = frames(8);
  ASSERT_EQ(one.size(), many.size());
  for (size_t k = 0; k < one.size(); ++k) EXPECT_EQ(one[k], many[k]) << "image " << k;
}

// rtao declares its falloff with raytraced's declaration (power_falloff_param.h): the same
// choices, power:K included (CONTRACT §3), and the same definition for the same settings.
TEST(Rtao, AcceptsEveryFalloffRaytracedDoes) {
  const EstimatorInfo rtao = rtao_estimator(), rt = raytraced_estimator();
  EXPECT_EQ(rtao.find_param("falloff")->choices, rt.find_param("falloff")->choices);
  EXPECT_EQ(rtao.find_param("falloff_k")->default_value, rt.find_param("falloff_k")->default_value);
  for (const std::string falloff : {"none", "linear", "sqrt", "exp", "power"}) {
    const AoDefinition a = rtao.definition(resolve_params(
        rtao.name, rtao.params, {{"t_max", 0.5}, {"falloff", falloff}, {"falloff_k", 3}}, "test"));
    const AoDefinition b = rt.definition(resolve_params(
        rt.name, rt.params, {{"dmax", 0.5}, {"falloff", falloff}, {"falloff_k", 3}}, "test"));
    EXPECT_EQ(a.falloff, b.falloff) << falloff;
    EXPECT_EQ(a.dmax, b.dmax) << falloff;
    EXPECT_EQ(a.weighting, b.weighting) << falloff;
  }
  const AoDefinition p = rtao.definition(resolve_params(
      rtao.name, rtao.params, {{"t_max", 0.5}, {"falloff", "power"}, {"falloff_k", 1}}, "test"));
  EXPECT_EQ(p.falloff, Falloff::linear);  // power:1 = linear
}

}  // namespace
}  // namespace aoeval
