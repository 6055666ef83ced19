// The temporal runner (frames.cpp) against closed forms (CONTRACT §10, issue 29's
// "It must show" 1): on a static-camera sequence an estimator without temporal design flickers by
// exactly its per-frame variance, and a deterministic one not at all.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"
#include "harness/evaluation/background_lane.h"
#include "harness/evaluation/evaluation.h"
#include "harness/scoring/metrics.h"

namespace aoeval {
namespace {

// A box on a floor seen from above at 64x48 for 8 frames, nothing moving: about half the covered
// pixels have 0 < AO < 1 (the floor around the box, the box's sides), where the flicker lives.
// `sequence`: the view's sequence object.
std::string sequence_scene(const std::string& sequence = R"({"frames": 8})") {
  const auto dir = testutil::test_temp_dir("sequence_eval");
  const std::string path = (dir / "still.json").string();
  std::ofstream(path) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.6, 0.6, 0.6]},
       "transform": {"translate": [0, 0.3, 0]}}],
    "views": [{"name": "still", "eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0], "fov_y_deg": 50,
               "width": 64, "height": 48, "sequence": )"
                      << sequence << "}]}";
  return path;
}
std::string static_sequence_scene() {
  return sequence_scene();
}

ResultRow run(EvaluationSession& session, const std::string& scene, const std::string& estimator,
              nlohmann::json overrides, bool seed_per_frame = true) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = scene;
  req.view = "still";
  req.seed_per_frame = seed_per_frame;
  Measurement m = session.measure(req);
  EXPECT_EQ(m.row.status, "ok");
  EXPECT_EQ(m.frames.size(), 7u) << "frames 0..6 scored as they ran, the last one left to score()";
  ResultRow row = session.score(m);
  EXPECT_EQ(m.frames.size(), 8u);
  // One scoring path: the row's plain keys are its last frame's, as score() scored it.
  if (row.status == "ok" && m.frames.size() == 8u) {
    EXPECT_EQ(m.frames.back().at("frame"), 7);
    for (const char* key : {"rmse", "ssim", "flip_mean", "rmse_excess"}) {
      EXPECT_EQ(row.metrics.at(key), m.frames.back().at(key)) << key;
      EXPECT_EQ(row.true_metrics.at(key), m.frames.back().at(std::string("true_") + key)) << key;
    }
  }
  return row;
}

// raytraced with 4 cosine rays and the random sampler: each frame's estimate is a mean of 4
// Bernoulli(a) visibilities, variance a(1 - a)/4, independent between frames (seed + k), so
// E[d^2] = 2 a(1 - a)/4 per pixel once the reference's own noise is removed. Tolerance 10 %: the
// mean of d^2 over 7 x ~3000 pixel-frames has a relative standard error of about 1.5 %.
TEST(SequenceEvaluation, RaytracedFlickerMatchesTheBernoulliVariance) {
  const std::string scene = static_sequence_scene();
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, /*disk_cache=*/false);
  const ResultRow row = run(session, scene, "raytraced", {{"rays", 4}, {"sampler", "random"}});
  const View& view = session.scene(scene).scene.view("still");
  const GBuffer& g = session.gbuffer(scene, view, 64, 48);
  const ReferenceImage& ref = session.reference(scene, view, 64, 48, true_ao_definition());
  double sum = 0.0, n = 0.0;
  for (size_t p = 0; p < g.pixel_count(); ++p) {
    if (!g.covered(p)) continue;
    const double a = ref.ao[p];
    sum += 2.0 * a * (1.0 - a) / 4.0;
    n += 1.0;
  }
  const double expected = sum / n;
  const double excess = row.metrics["temporal_rmse_excess"].get<double>();
  EXPECT_GT(expected, 0.01);  // the scene has partly occluded pixels
  EXPECT_NEAR(excess * excess / expected, 1.0, 0.10) << "expected " << expected;
  std::printf("temporal_rmse_excess^2 %.6f, mean 2a(1-a)/4 %.6f, ratio %.4f\n", excess * excess,
              expected, excess * excess / expected);
  EXPECT_EQ(row.metrics["seq_frames"], 8);
  EXPECT_EQ(row.repetitions, 8);  // one timed run per frame
  // Nothing moves: nothing is disoccluded, so there is nothing to settle.
  EXPECT_TRUE(row.metrics["settle_frames"].is_null());
  EXPECT_TRUE(row.metrics["disocclusion_rmse_excess"].is_null());
  // A still camera over a still scene: no reference changes along a trajectory beyond its noise
  // (0.05 + 3 sigma), so there is no lag to measure (CONTRACT §10).
  EXPECT_TRUE(row.metrics["lag_rmse_excess"].is_null());
}

// With one seed for every frame the same estimate repeats: no flicker beyond the reference's.
TEST(SequenceEvaluation, OneSeedForEveryFrameDoesNotFlicker) {
  const std::string scene = static_sequence_scene();
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, false);
  const ResultRow row =
      run(session, scene, "raytraced", {{"rays", 4}, {"sampler", "random"}}, false);
  EXPECT_LE(row.metrics["temporal_rmse_excess"].get<double>(), 0.01);
  EXPECT_NE(row.run_name.find("seed_per_frame:false"), std::string::npos);
}

// constant gives the same value every frame: temporal_rmse_excess <= 1e-3.
TEST(SequenceEvaluation, ConstantDoesNotFlicker) {
  const std::string scene = static_sequence_scene();
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, false);
  const ResultRow row = run(session, scene, "constant", nlohmann::json::object());
  EXPECT_LE(row.metrics["temporal_rmse_excess"].get<double>(), 1e-3);
  EXPECT_GT(row.metrics["seq_rmse_excess"].get<double>(), 0.05);  // but it is wrong everywhere
  EXPECT_EQ(row.metrics["converge_frames"], 0);
}

// Issue 42, must-show 4: nothing changes between the frames of the static sequence, so its
// reference is traced once (frame 0's, with seed + 0) and every frame scores against it. The
// constant estimator repeats itself and so does the reference: d = 0 at every pixel and no
// reference noise is removed (the frames share it), so temporal_rmse_excess is exactly 0. A
// bounded raytraced point then asks two definitions (its own and true AO) of the same static
// view: one more trace, shared by both.
TEST(SequenceEvaluation, StaticSequenceTracesOneReference) {
  const std::string scene = static_sequence_scene();
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, false);
  const ResultRow row = run(session, scene, "constant", nlohmann::json::object());
  EXPECT_EQ(session.reference_counts().traces, 1u);
  EXPECT_EQ(session.reference_counts().references, 1u);  // constant's definition is true AO
  EXPECT_EQ(row.metrics["temporal_rmse"].get<double>(), 0.0);
  EXPECT_EQ(row.metrics["temporal_rmse_excess"].get<double>(), 0.0);
  EXPECT_EQ(row.true_metrics["temporal_rmse_excess"].get<double>(), 0.0);
  // The row says so: one reference image for its 8 frames, which the precision rule pools as one
  // (reports/regression.cpp metric_noise_sigma, tools/reference_precision.py).
  EXPECT_EQ(row.metrics["seq_frames"], 8);
  EXPECT_EQ(row.metrics["seq_reference_frames"], 1);
  EXPECT_EQ(row.true_metrics["seq_reference_frames"], 1);
  const View& view = session.scene(scene).scene.view("still");
  for (int k = 0; k < 8; ++k) EXPECT_EQ(session.reference_frame(scene, view, k), 0) << k;

  EvaluationSession bounded(ReferenceSpec{}, TimingSpec{0, 1}, false);
  run(bounded, scene, "raytraced", {{"rays", 4}, {"dmax", 0.5}, {"falloff", "linear"}});
  EXPECT_EQ(bounded.reference_counts().traces, 1u);
  EXPECT_EQ(bounded.reference_counts().references, 2u);
}

// A cold session keeps what it traces (the asked reference and its companions) in memory rather
// than reading back the entries it wrote (issue 42): every reference and every score equal, bit for
// bit, what a warm session reads from that cache, and the warm one traces nothing.
TEST(SequenceEvaluation, ColdSessionScoresWhatAWarmOneReads) {
  const std::string scene = static_sequence_scene();
  const auto cache = testutil::test_temp_dir("sequence_eval_cache");
  setenv("AOEVAL_CACHE", cache.c_str(), 1);
  const nlohmann::json overrides = {{"rays", 4}, {"dmax", 0.5}, {"falloff", "linear"}};
  EvaluationSession cold(ReferenceSpec{}, TimingSpec{0, 1}, true);
  const ResultRow cold_row = run(cold, scene, "raytraced", overrides);
  EXPECT_EQ(cold.reference_counts().references, 2u);  // traced together: one is a companion
  EvaluationSession warm(ReferenceSpec{}, TimingSpec{0, 1}, true);
  const ResultRow warm_row = run(warm, scene, "raytraced", overrides);
  EXPECT_EQ(warm.reference_counts().traces, 0u);
  EXPECT_EQ(cold_row.metrics.dump(), warm_row.metrics.dump());
  EXPECT_EQ(cold_row.true_metrics.dump(), warm_row.true_metrics.dump());
  const View& view = cold.scene(scene).scene.view("still");
  const EstimatorInfo& raytraced = find_estimator("raytraced");
  const AoDefinition bounded =
      raytraced.definition(resolve_params("raytraced", raytraced.params, overrides, "test"));
  for (const AoDefinition& d : {bounded, true_ao_definition()}) {
    const ReferenceImage& a = cold.reference(scene, view, 64, 48, d);
    const ReferenceImage& b = warm.reference(scene, view, 64, 48, d);
    EXPECT_EQ(a.ao, b.ao);
    EXPECT_EQ(a.stderr_ao, b.stderr_ao);
    EXPECT_EQ(a.bent, b.bent);
    EXPECT_EQ(a.bent_stderr, b.bent_stderr);
    EXPECT_EQ(a.coverage, b.coverage);
    EXPECT_EQ(a.spp, b.spp);
  }
  unsetenv("AOEVAL_CACHE");
}

// Two points of one moving sequence in a cold session whose background work runs on a lane, as
// the runners run it (issue 42): the frames but the last scored there in order, the companions'
// cache entries written there, the second point served its references from memory. Every row and
// frame row equals, bit for bit, what a session doing all of it at once gives, and what the lane
// wrote is what a warm session reads: it traces nothing.
TEST(SequenceEvaluation, ALaneScoresAndWritesWhatTheRunnersThreadDoes) {
  const auto dir = testutil::test_temp_dir("sequence_eval_lane");
  const std::string scene = sequence_scene(
      R"({"frames": 6, "camera": [{"frame": 5, "eye": [1.3, 1.2, 0.8], "target": [0, 0.1, 0]}]})");
  const nlohmann::json bounded = {{"rays", 4}, {"dmax", 0.5}, {"falloff", "linear"}};
  auto request = [&](const std::string& estimator, const nlohmann::json& overrides) {
    EvaluationRequest req;
    req.estimator = &find_estimator(estimator);
    req.overrides = overrides;
    req.scene = scene;
    req.view = "still";
    return req;
  };
  const std::vector<EvaluationRequest> points = {request("raytraced", bounded),
                                                 request("constant", nlohmann::json::object())};
  struct Scored {
    std::vector<std::string> rows, frames;
  };
  auto score_all = [&](const std::string& cache, bool lane_on) {
    setenv("AOEVAL_CACHE", cache.c_str(), 1);
    EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, true);
    for (const EvaluationRequest& req : points) session.plan_references(req);
    Scored out;
    {
      BackgroundLane lane;
      if (lane_on)
        session.set_background([&lane](std::function<void()> job) { lane.post(std::move(job)); });
      for (const EvaluationRequest& req : points) {
        auto m = std::make_shared<Measurement>(session.measure(req));
        lane.post([&, m] {
          const ResultRow row = session.score(*m);
          out.rows.push_back(row.metrics.dump() + row.true_metrics.dump());
          for (nlohmann::json f : m->frames) {
            f.erase("time_ms");  // the one column that differs between runs
            out.frames.push_back(f.dump());
          }
        });
      }
      lane.drain();
      session.set_background(nullptr);
    }
    EXPECT_EQ(session.reference_counts().traces, 6u) << "one pass a frame for both points";
    return out;
  };
  const Scored at_once = score_all((dir / "cache_a").string(), false);
  const Scored on_lane = score_all((dir / "cache_b").string(), true);
  ASSERT_EQ(on_lane.frames.size(), 12u);
  EXPECT_EQ(on_lane.rows, at_once.rows);
  EXPECT_EQ(on_lane.frames, at_once.frames);
  // Each point alone in a warm session reads every reference from what the lane wrote.
  setenv("AOEVAL_CACHE", (dir / "cache_b").c_str(), 1);
  for (size_t i = 0; i < points.size(); ++i) {
    EvaluationSession warm(ReferenceSpec{}, TimingSpec{0, 1}, true);
    const ResultRow row = warm.evaluate(points[i]);
    EXPECT_EQ(warm.reference_counts().traces, 0u);
    EXPECT_EQ(row.metrics.dump() + row.true_metrics.dump(), on_lane.rows.at(i)) << i;
    EXPECT_EQ(row.metrics["seq_reference_frames"], 6) << "the camera moves: one a frame";
  }
  unsetenv("AOEVAL_CACHE");
}

// The points of a sequence view share FLIP's reference side of each frame's references (prepared
// by the first point that scores against it, ReferenceStore::flip_frame_reference): a frame of a
// one-frame sequence is scored, by two points one after the other, exactly as the same view's still
// is, where nothing is shared between definitions (it fails when a point's true-AO scoring takes
// the side of its matched reference).
TEST(SequenceEvaluation, PointsOfAViewShareFlipsReferenceSideAndScoreAsAStill) {
  const auto dir = testutil::test_temp_dir("sequence_eval_flip_side");
  const std::string scene = (dir / "two_views.json").string();
  const std::string camera = R"("eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0], "fov_y_deg": 50,
      "width": 64, "height": 48)";
  std::ofstream(scene) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.6, 0.6, 0.6]},
       "transform": {"translate": [0, 0.3, 0]}}],
    "views": [{"name": "still", )"
                       << camera << R"(}, {"name": "one", )" << camera
                       << R"(, "sequence": {"frames": 1}}]})";
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, false);
  const nlohmann::json bounded = {{"rays", 4}, {"dmax", 0.5}, {"falloff", "linear"}};
  auto row = [&](const std::string& view, const std::string& estimator,
                 const nlohmann::json& overrides) {
    EvaluationRequest req;
    req.estimator = &find_estimator(estimator);
    req.overrides = overrides;
    req.scene = scene;
    req.view = view;
    return session.evaluate(req);
  };
  const ResultRow seq_bounded = row("one", "raytraced", bounded);
  const ResultRow seq_constant = row("one", "constant", nlohmann::json::object());
  const ResultRow still_bounded = row("still", "raytraced", bounded);
  const ResultRow still_constant = row("still", "constant", nlohmann::json::object());
  for (const std::string& key : metric_keys()) {
    EXPECT_EQ(seq_bounded.metrics.at(key), still_bounded.metrics.at(key)) << key;
    EXPECT_EQ(seq_bounded.true_metrics.at(key), still_bounded.true_metrics.at(key)) << key;
    EXPECT_EQ(seq_constant.true_metrics.at(key), still_constant.true_metrics.at(key)) << key;
  }
  EXPECT_NE(still_bounded.metrics.at("flip_mean"), still_bounded.true_metrics.at("flip_mean"));
}

}  // namespace
}  // namespace aoeval
