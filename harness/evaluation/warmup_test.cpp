// Which points the timing's warm-up runs for (frames.cpp, EstimatorInfo::warms_up(), issue 42):
// counted runs of a wrapped constant estimator declared with each backend, a still and a sequence.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>

#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {
namespace {

// `constant`, counting the runs of every instance it creates.
EstimatorInfo counted(Backend backend, bool first_run_is_warm, std::atomic<int>& runs) {
  EstimatorInfo info = find_estimator("constant");
  info.backend = backend;
  info.first_run_is_warm = first_run_is_warm;
  struct Counting : Estimator {
    std::unique_ptr<Estimator> inner;
    std::atomic<int>* runs;
    void prepare(const EstimateContext& c) override { inner->prepare(c); }
    EstimateResult run(const EstimateContext& c) override {
      ++*runs;
      return inner->run(c);
    }
  };
  info.create = [create = info.create, &runs](const ParamSet& p) -> std::unique_ptr<Estimator> {
    auto e = std::make_unique<Counting>();
    e->inner = create(p);
    e->runs = &runs;
    return e;
  };
  return info;
}

int runs_of(Backend backend, bool first_run_is_warm, const std::string& view) {
  const auto dir = testutil::test_temp_dir("warmup");
  const std::string scene = (dir / "box.json").string();
  std::ofstream(scene) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}}],
    "views": [{"name": "still", "eye": [0.9, 1.4, 1.3], "target": [0, 0, 0], "width": 16,
               "height": 12},
              {"name": "seq", "eye": [0.9, 1.4, 1.3], "target": [0, 0, 0], "width": 16,
               "height": 12, "sequence": {"frames": 3}}]})";
  std::atomic<int> runs{0};
  const EstimatorInfo info = counted(backend, first_run_is_warm, runs);
  EvaluationSession session(ReferenceSpec{.spp = 4}, TimingSpec{2, 3}, false);
  EvaluationRequest req;
  req.estimator = &info;
  req.scene = scene;
  req.view = view;
  EXPECT_EQ(session.evaluate(req).status, "ok");
  return runs.load();
}

TEST(Warmup, RunsForVulkanAndProcessEstimatorsUnlessTheyDeclareTheirFirstRunWarm) {
  // A still: 2 warm-up runs, then 3 timed; a 3-frame sequence: 2 warm-up runs (a throw-away
  // instance on frame 0), then one run a frame.
  for (const std::string view : {"still", "seq"}) {
    EXPECT_EQ(runs_of(Backend::vulkan, false, view), 2 + 3) << view;
    EXPECT_EQ(runs_of(Backend::process, false, view), 2 + 3) << view;
    EXPECT_EQ(runs_of(Backend::vulkan, true, view), 3) << view;
    EXPECT_EQ(runs_of(Backend::cpu, false, view), 3) << view;
    EXPECT_EQ(runs_of(Backend::embree, false, view), 3) << view;
  }
  EXPECT_FALSE(find_estimator("shadowmap-ao").warms_up());
  EXPECT_TRUE(find_estimator("hbao-split").warms_up());
  EXPECT_TRUE(find_estimator("gtao").warms_up());
  EXPECT_FALSE(find_estimator("raytraced").warms_up());
}

}  // namespace
}  // namespace aoeval
