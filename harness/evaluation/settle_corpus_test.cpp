// settle_frames and lag_rmse_excess on the corpus's sequences (CONTRACT §10; issue 43, "It must
// show" 3), scored by the temporal runner at 64x48 with 64-ray references:
//  - constant keeps no history and no noise: settle_frames is 0 on every corpus sequence view
//    (blank where no trajectory qualifies: a view where nothing is ever disoccluded has no ages).
//    settle_frames compares each trajectory with itself, its error at age g against 1.1 x its
//    error pooled over ages 9..12, on trajectories whose truth holds still, so a deterministic
//    estimate without history has the same error at every age;
//  - lag_rmse_excess is blank on a static camera over a static scene (the still views: no
//    reference changes along a trajectory by more than 0.05 + 3 sigma).
// raytraced at 1 and 4 rays is not checked here: at this size and reference count it reads 1 on
// grass-field/fly and 4 on dragon/walk at 1 ray: a trajectory "holds still" within 0.02 + 3 sigma
// of 64-ray references, about 0.2, which admits points whose truth rises as the dragon walks away,
// and a fresh-ray estimate's noise a(1 - a) falls with it (issue 43 leaves this open).
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
                      const std::string& estimator, nlohmann::json overrides) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = sv.scene;
  req.view = sv.view;
  req.width = 64;
  req.height = 48;
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

}  // namespace
}  // namespace aoeval
