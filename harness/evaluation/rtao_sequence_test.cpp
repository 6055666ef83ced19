// rtao over a static-camera sequence, scored by the temporal runner (issue 31, "It must show" 1),
// on the corpus's bunny/still and tree-ground/still at 96x72 (16 frames, nothing moving), all
// rows at 1 ray per pixel per frame and the same AO definition (cosine, unbounded):
//  - rtao's steady_rmse_excess (frames 8..15) is at most half its frame-0 rmse_excess: frame 0
//    has no history (only the a-trous passes over one frame's rays), the steady frames a history
//    of 9-16 frames;
//  - its temporal_rmse_excess is at most 0.3 x raytraced's at 1 ray (fresh rays every frame:
//    flicker sqrt(2 a (1 - a)) per pixel, about 0.4 here), since a pixel of history L changes by
//    alpha (x - h), alpha ~ 1/L, from frame to frame;
//  - with the temporal stage and the a-trous passes off, rtao is 1-ray AO, as raytraced is: its
//    seq_rmse_excess equals raytraced's within 6 %. Each is sqrt(mean a(1 - a)) over ~100 000
//    pixel-frames of one Bernoulli ray: the relative standard error of a mean of squared errors
//    (x - a)^2 (variance a(1 - a)(1 - 2a)^2 <= its mean) is at most 1/sqrt(n_eff), under 1 % with
//    n_eff >= 10^4 even if only a tenth of the pixels are partly occluded; halved for the rms and
//    doubled for a difference of two, 6 % is over 6 standard errors. So the gain above is the
//    denoiser's.
// The references are 128 rays (stderr <= 0.044 a pixel), whose noise rmse_excess removes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {
namespace {

struct Scored {
  ResultRow row;
  std::vector<double> frame_excess;
};

Scored run(EvaluationSession& session, const std::string& scene, const std::string& estimator,
           nlohmann::json overrides) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = scene;
  req.view = "still";
  req.width = 96;
  req.height = 72;
  Measurement m = session.measure(req);
  EXPECT_EQ(m.row.status, "ok");
  Scored s;
  s.row = session.score(m);
  for (const auto& f : m.frames) s.frame_excess.push_back(f["rmse_excess"].get<double>());
  return s;
}

double key(const Scored& s, const char* k) {
  return s.row.metrics.at(k).get<double>();
}

class RtaoStaticSequence : public ::testing::TestWithParam<std::string> {};

TEST_P(RtaoStaticSequence, TheDenoiserNotTheRaysMakesTheGain) {
  const std::string scene = GetParam();
  ReferenceSpec reference;
  reference.spp = 128;
  EvaluationSession session(reference, TimingSpec{0, 1}, /*disk_cache=*/false);
  const Scored rtao = run(session, scene, "rtao", {{"rays", 1}});
  const Scored raw = run(session, scene, "raytraced", {{"rays", 1}});
  const Scored off =
      run(session, scene, "rtao", {{"rays", 1}, {"temporal", false}, {"atrous_iterations", 0}});
  ASSERT_EQ(rtao.frame_excess.size(), 16u);
  // A sequence row: no still-frame note.
  EXPECT_FALSE(rtao.row.params.value("derived", nlohmann::json::object()).contains("still_frame"));

  const double frame0 = rtao.frame_excess.front(), steady = key(rtao, "steady_rmse_excess");
  EXPECT_LE(steady, 0.5 * frame0) << scene;
  const double flicker = key(rtao, "temporal_rmse_excess");
  const double raw_flicker = key(raw, "temporal_rmse_excess");
  EXPECT_LE(flicker, 0.3 * raw_flicker) << scene;
  const double off_excess = key(off, "seq_rmse_excess"), raw_excess = key(raw, "seq_rmse_excess");
  EXPECT_NEAR(off_excess / raw_excess, 1.0, 0.06) << scene;
  std::printf(
      "%s 96x72, 16 frames, 1 ray: rtao frame-0 rmse_excess %.4f, steady %.4f (ratio %.3f); "
      "temporal_rmse_excess rtao %.4f, raytraced %.4f (ratio %.3f); seq_rmse_excess rtao "
      "without temporal and a-trous %.4f, raytraced %.4f (ratio %.3f)\n",
      scene.c_str(), frame0, steady, steady / frame0, flicker, raw_flicker, flicker / raw_flicker,
      off_excess, raw_excess, off_excess / raw_excess);
}

INSTANTIATE_TEST_SUITE_P(Corpus, RtaoStaticSequence, ::testing::Values("bunny", "tree-ground"),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

}  // namespace
}  // namespace aoeval
