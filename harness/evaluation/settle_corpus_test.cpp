// settle_frames and lag_rmse_excess on the corpus's sequences (CONTRACT §10; issue 43, "It must
// show" 3), scored by the temporal runner at 64x48 with 64-ray references:
//  - constant keeps no history and no noise: settle_frames is 0 on every corpus sequence view
//    (blank where no trajectory qualifies: a view where nothing is ever disoccluded has no ages).
//    settle_frames compares each trajectory with itself, its error at age g against 1.1 x its
//    error pooled over ages 9..12, on trajectories whose truth holds still, so a deterministic
//    estimate without history has the same error at every age;
//  - lag_rmse_excess is blank on a static camera over a static scene (the still views: no
//    reference changes along a trajectory by more than 0.05 + 3 sigma).
// raytraced at 1 and 4 rays (fresh rays, no history) is FreshRaysSettleAtOnce below.
#include <gtest/gtest.h>

#include <cstdio>

#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"
#include "scenes/corpus.h"

namespace aoeval {
namespace {

struct SequenceView {
  std::string scene, view;
  bool still;  // no camera path and no moving object
};

std::vector<SequenceView> corpus_sequence_views(EvaluationSession& session) {
  std::vector<SequenceView> out;
  for (const std::string& name : corpus_names())
    for (const View& v : session.scene(name).scene.views)
      if (v.sequence)
        out.push_back({name, v.name, v.sequence->camera.empty() && v.sequence->objects.empty()});
  return out;
}

nlohmann::json scores(EvaluationSession& session, const SequenceView& sv,
                      const std::string& estimator, nlohmann::json overrides, int width = 64,
                      int height = 48) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = sv.scene;
  req.view = sv.view;
  req.width = width;
  req.height = height;
  Measurement m = session.measure(req);
  EXPECT_EQ(m.row.status, "ok");
  return session.score(m).metrics;
}

TEST(SettleOnTheCorpus, NoHistorySettlesAtOnceAndAStillViewHasNoLag) {
  ReferenceSpec reference;
  reference.spp = 64;
  EvaluationSession session(reference, TimingSpec{0, 1}, /*disk_cache=*/false);
  const std::vector<SequenceView> views = corpus_sequence_views(session);
  ASSERT_GE(views.size(), 9u);
  int qualified = 0;
  for (const SequenceView& sv : views) {
    const std::vector<std::pair<std::string, nlohmann::json>> runs = {
        {"constant", nlohmann::json::object()}};
    for (const auto& [estimator, overrides] : runs) {
      const nlohmann::json k = scores(session, sv, estimator, overrides);
      const nlohmann::json& settle = k["settle_frames"];
      std::printf("%s/%s %s %s: settle_frames %s, lag_rmse_excess %s\n", sv.scene.c_str(),
                  sv.view.c_str(), estimator.c_str(), overrides.dump().c_str(),
                  settle.dump().c_str(), k["lag_rmse_excess"].dump().c_str());
      if (!settle.is_null() && estimator == "constant") {
        EXPECT_EQ(settle, 0) << sv.scene << "/" << sv.view;
        ++qualified;
      }
      if (sv.still) {
        EXPECT_TRUE(k["lag_rmse_excess"].is_null()) << sv.scene << "/" << sv.view << estimator;
      }
    }
  }
  // The moving views do disocclude: they had trajectories to check.
  EXPECT_GE(qualified, 4);
}

// raytraced keeps no history either, but its estimate is noise: settle_frames compares the rms
// error of N trajectories at age g with 1.1 x the same trajectories' at ages 9..12, so it reads 0
// only where N is large enough for that ratio's noise to stay well under 10 %. Measured with 4
// seeds x {1, 4} rays (64-ray references; r0 = age 0's ratio, sd = its spread over ages 0..12):
//  - dragon/walk: r0 1.16 at 64x48 (sd 0.10; settle 0 to 7), 1.08 at 128x96 (sd 0.05; 0 to 4),
//    1.04 at 160x120 (sd 0.02; 0 in 8 of 8), 1.04 at 320x240 (sd 0.02). An excess of about 4 %
//    at age 0 is systematic (r0 > 1 in all 16 runs at 128x96 and 160x120; at 64x48 a mean of
//    1.14-1.15 with 256- and 1024-ray references too, whose "holds still" tolerance is 2-4 x
//    narrower): the floor the dragon uncovers brightens within that tolerance, and a 1-ray
//    estimate's variance a (1 - a) falls as a nears 1. At 64x48 the fringe next to the dragon is
//    (likely) a larger share of the trajectories, hence 1.16.
//  - rolling-ball/roll: r0 0.92-1.04 at 64x48 (sd 0.02-0.06), 0.98-1.02 at 160x120 (sd 0.01-0.02).
//  - bunny/orbit (24 frames): sd 0.03-0.07 at 160x120, one run of 8 reads 1 (r0 1.101).
//  - grass-field/fly: sd 0.14-0.29 at 160x120 (2 of 8 read 1); q3-20kdm2/walk: sd 0.06-0.17 at
//    160x120 (1 of 8 reads 1); forest-10k/fly: sd 0.3-0.5 at 64x48; forest-1k/fly: no trajectory
//    at 64x48; oa-dm4/walk reads 0 in 8 of 8 at 160x120, but with an rmse_excess of 0 at every
//    age (its few trajectories' error is within the references' noise), a 0 that shows nothing. A
//    flying or walking camera keeps few points in view 13 frames with their truth still.
//  - At the default suite's 320x240 (64-ray references, seeds 7-10 x {1, 4} rays; `aoeval
//    sweep` over the four seeds, r_g from each point's sequence.json settle_excess_by_age):
//    bunny/orbit r0 0.94-0.98 and every age 0..8 within 0.92-1.05, settle 0 in 8 of 8;
//    grass-field/fly settle 0 in 8 of 8 too, but r0 up to 1.097 and single ages up to 1.37, a 0
//    by a margin the next change of seed or reference could take away; q3-20kdm2/walk 8 of 8 (r0
//    0.87-1.07), forest-1k/fly 8 of 8 (r0 0.92-1.08), oa-dm4/walk 8 of 8 (an rmse_excess of 0 at
//    every age), forest-10k/fly 7 of 8 (r0 0.91-1.16: seed 9 at 1 ray reads 1). So 39 of the 40
//    runs on the five views left out here read 0, and the one that does not is the statistic's
//    noise (settle_frames is 0 exactly when r0 <= 1.1, and r0 spreads by about 0.08 there). Their
//    references cost 47 s a view at 320x240 (`aoeval sweep
//    harness/specs/settle-raytraced-320.json`, 486 s in all), which is why they are measured, not
//    run here.
// So this asserts settle_frames = 0 where the size gives trajectories enough: dragon/walk and
// rolling-ball/roll (the corpus's moving objects) at 160x120, bunny/orbit at 320x240.
TEST(SettleOnTheCorpus, FreshRaysSettleAtOnce) {
  ReferenceSpec reference;
  reference.spp = 64;
  EvaluationSession session(reference, TimingSpec{0, 1}, /*disk_cache=*/false);
  struct Case {
    SequenceView view;
    int width, height;
  };
  for (const Case& c :
       {Case{{"dragon", "walk", false}, 160, 120}, Case{{"rolling-ball", "roll", false}, 160, 120},
        Case{{"bunny", "orbit", false}, 320, 240}})
    for (int rays : {1, 4}) {
      const SequenceView& sv = c.view;
      const nlohmann::json k =
          scores(session, sv, "raytraced", {{"rays", rays}}, c.width, c.height);
      std::printf("%s/%s raytraced %d rays, %dx%d: settle_frames %s\n", sv.scene.c_str(),
                  sv.view.c_str(), rays, c.width, c.height, k["settle_frames"].dump().c_str());
      EXPECT_EQ(k["settle_frames"], 0) << sv.scene << "/" << sv.view << " rays " << rays;
    }
}

}  // namespace
}  // namespace aoeval
