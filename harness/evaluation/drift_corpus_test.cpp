// No drift from the history (issue 43, "It must show" 1's drift half), on the corpus sequences
// with motion: rolling-ball/roll (a ball rolling by a wall and a box, the camera moving) and
// dragon/walk, at 160x120 with 64-ray references, the temporal runner's seeds.
//
// The test, the last frame's rmse_excess against frame 8's, reads the content as much as
// the history on these two sequences: their late frames are harder for every screen-space
// estimator, with or without history, converged or not (320x240, last / frame 8: gtao-cpu with
// 32 slices x 32 steps 1.174 on roll and 1.091 on walk, hbao-split-cpu with Nd 32, Ns 32 1.496 on
// roll), and a 1-slice gtao frame's error depends on its rotation (frame 8's gives 0.038 on roll,
// the 6-frame cycle's rms is 0.070). So this test compares whole cycles and takes out the
// content's own growth:
//   cycle ratio c = rms(rmse_excess over the last 6 frames) / rms(over frames 6..11)
// (frames 6..11: the rotation cycle of `rotations` 6 that holds frame 8), and asserts for each
// estimator with history c <= max(1.05, 1.05 c_twin), its twin being the same estimator without
// history (gtao 6 slices, the work of the 6-frame cycle; hbao-split without `temporal`). rtao's
// rays have no bias for a twin to carry, and its bound is 1.05 itself.
// The test can fail: the stage as it was before issue 43's anti-lag (`antilag` 0) drifts on walk
// beyond the bound for all three (measured: gtao 1.220 against 1.187, hbao-split 1.109 against
// 1.05, rtao 1.167 against 1.05), and this asserts that too. On roll the anti-lag-free stage
// passes: its lag inflates frames 6..11 (gtao 0.074 there against 0.056 with the anti-lag).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {
namespace {

struct Curve {
  std::vector<double> excess;  // rmse_excess per frame
  double cycle_ratio() const {
    // NaN (every comparison with it fails) when a run gave fewer frames than the two cycles.
    if (excess.size() < 12) return std::nan("");
    auto rms = [](auto first, auto last) {
      double sum = 0.0;
      for (auto it = first; it != last; ++it) sum += *it * *it;
      return std::sqrt(sum / static_cast<double>(last - first));
    };
    return rms(excess.end() - 6, excess.end()) / rms(excess.begin() + 6, excess.begin() + 12);
  }
};

Curve frames_of(EvaluationSession& session, const std::string& scene, const std::string& view,
                const std::string& estimator, nlohmann::json overrides) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = scene;
  req.view = view;
  req.width = 160;
  req.height = 120;
  Measurement m = session.measure(req);
  EXPECT_EQ(m.row.status, "ok");
  session.score(m);
  Curve c;
  for (const auto& f : m.frames) c.excess.push_back(f["rmse_excess"].get<double>());
  return c;
}

struct Temporal {
  const char* estimator;
  nlohmann::json history;              // the estimator with its history, at its defaults
  std::optional<nlohmann::json> twin;  // the same estimator without history
};

TEST(DriftOnTheCorpus, HistoryAddsNoDriftToTheContentsOwn) {
  ReferenceSpec reference;
  reference.spp = 64;
  EvaluationSession session(reference, TimingSpec{0, 1}, /*disk_cache=*/false);
  const std::vector<Temporal> estimators = {
      {"gtao-cpu",
       {{"slices", 1}, {"rotations", 6}, {"temporal", true}},
       nlohmann::json{{"slices", 6}, {"rotations", 6}}},
      {"hbao-split-cpu", {{"temporal", true}}, nlohmann::json::object()},
      {"rtao", nlohmann::json::object(), std::nullopt}};
  for (const auto& [scene, view] : {std::pair<std::string, std::string>{"rolling-ball", "roll"},
                                    std::pair<std::string, std::string>{"dragon", "walk"}}) {
    for (const Temporal& t : estimators) {
      const Curve with = frames_of(session, scene, view, t.estimator, t.history);
      ASSERT_GE(with.excess.size(), 24u);
      const double twin =
          t.twin ? frames_of(session, scene, view, t.estimator, *t.twin).cycle_ratio() : 0.0;
      const double bound = std::max(1.05, 1.05 * twin);
      nlohmann::json no_antilag = t.history;
      no_antilag["antilag"] = 0;
      const double before =
          view == "walk" ? frames_of(session, scene, view, t.estimator, no_antilag).cycle_ratio()
                         : 0.0;
      std::printf(
          "%s/%s %s: frame 8 -> last %.3f, cycle ratio %.3f (no history %.3f, bound %.3f); "
          "antilag 0: %.3f\n",
          scene.c_str(), view.c_str(), t.estimator, with.excess.back() / with.excess[8],
          with.cycle_ratio(), twin, bound, before);
      EXPECT_LE(with.cycle_ratio(), bound) << scene << "/" << view << " " << t.estimator;
      if (view == "walk") {
        EXPECT_GT(before, bound) << "antilag 0, " << t.estimator;
      }
    }
  }
}

}  // namespace
}  // namespace aoeval
