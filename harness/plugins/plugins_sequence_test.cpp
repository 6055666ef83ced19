// Plug-ins through the temporal runner (harness/evaluation/frames.cpp, CONTRACT §10):
// issue 29's must-show 4a (a GLSL plug-in that averages aoeval_history with its new frame flickers
// less than the same shader without history, by the closed form of an exponential average), and a
// "protocol": "frames" program started once per sequence point, its crash a skipped row.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "base/testing/test_temp_dir.h"
#include "estimators/registry.h"
#include "estimators/vulkan/vk_context.h"
#include "harness/evaluation/evaluation.h"

namespace aoeval {
namespace {

namespace fs = std::filesystem;

// A box on a floor seen from above at 64x48 for 8 frames, nothing moving (as in
// sequence_evaluation_test.cpp): the floor around the box and its sides are partly occluded.
std::string static_sequence_scene() {
  const auto dir = testutil::test_temp_dir("plugins_sequence");
  const std::string path = (dir / "still.json").string();
  std::ofstream(path) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.6, 0.6, 0.6]},
       "transform": {"translate": [0, 0.3, 0]}}],
    "views": [{"name": "still", "eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0], "fov_y_deg": 50,
               "width": 64, "height": 48, "sequence": {"frames": 8}}]})";
  return path;
}

Measurement measure(EvaluationSession& session, const std::string& scene,
                    const std::string& estimator, nlohmann::json overrides) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = scene;
  req.view = "still";
  return session.measure(req);
}

// The expected ratio of frame-to-frame difference variances, exponential average with weight w
// against its independent frames y_k (variance s^2 each): x_0 = y_0, x_k = (1 - w) y_k + w x_{k-1}.
// x_k - x_{k-1} = sum_j c_kj y_j with c_kk = 1 - w, c_kj = -(1 - w)^2 w^(k-1-j) for 1 <= j < k and
// c_k0 = -(1 - w) w^(k-1) (k = 1: c_10 = -(1 - w)); its variance is s^2 sum_j c_kj^2, against
// 2 s^2 without history. temporal_rmse_excess^2 is the mean over frames 1..F-1 (and pixels, whose
// s^2 factors out).
double exponential_average_ratio(double w, int frames) {
  double sum = 0.0;
  for (int k = 1; k < frames; ++k) {
    double c2 = (1 - w) * (1 - w) + std::pow((1 - w) * std::pow(w, k - 1), 2.0);
    for (int j = 1; j < k; ++j) c2 += std::pow((1 - w) * (1 - w) * std::pow(w, k - 1 - j), 2.0);
    sum += c2 / 2.0;
  }
  return sum / (frames - 1);
}

// Must-show 4a: history-ssao (shipped) with w = 0.8 against w = 0 (the same shader, history
// unread). A static camera: motion is 0, so its reprojection reads the same pixel. Both runs draw
// the same per-frame noise (seed + k), so their new estimates y_k agree and only the average
// differs: the ratio of temporal_rmse_excess^2 must be the closed form (0.0290 for 8 frames).
// Tolerance 20 %: about 1,500 partly occluded pixels x 7 frame pairs, correlated between
// consecutive pairs under the average, give the ratio a relative standard error near 4 %; the
// reference (1024 rays, stderr <= 0.016) adds a noise of its own that the excess removes up to
// the error of its stderr estimate, a further few per cent of the w = 0.8 value.
TEST(PluginsOverTime, HistoryLowersFlickerByTheExponentialAverage) {
  std::string why;
  if (!vk::shared_context(&why)) GTEST_SKIP() << "no Vulkan device: " << why;
  const std::string scene = static_sequence_scene();
  ReferenceSpec reference;
  reference.spp = 1024;
  EvaluationSession session(reference, TimingSpec{0, 1}, /*disk_cache=*/false);
  auto flicker = [&](double w) {
    Measurement m = measure(session, scene, "history-ssao", {{"history", w}});
    EXPECT_EQ(m.row.status, "ok");
    const ResultRow row = session.score(m);
    EXPECT_EQ(m.frames.size(), 8u);
    return row.metrics["temporal_rmse_excess"].get<double>();
  };
  const double without = flicker(0.0), with = flicker(0.8);
  const double expected = exponential_average_ratio(0.8, 8);
  const double ratio = (with * with) / (without * without);
  std::printf(
      "temporal_rmse_excess: history 0 %.5f, history 0.8 %.5f; ratio of squares %.4f, "
      "closed form %.4f\n",
      without, with, ratio, expected);
  EXPECT_GT(without, 0.03) << "4 samples a frame flicker";
  EXPECT_LT(with, without);
  EXPECT_NEAR(ratio / expected, 1.0, 0.20);
}

// A Python (standard library) frames program through the runner: started once for the 8 frames,
// each frame's seed + k in P.json; a crash at frame 3 is the point's skipped row.
TEST(PluginsOverTime, AFramesProgramRunsOncePerSequencePoint) {
  const fs::path dir = testutil::test_temp_dir("plugins_sequence") / "counting";
  fs::create_directories(dir);
  std::ofstream(dir / "estimator.json") << R"({"name": "counting-frames", "summary": "s",
      "kind": "process", "protocol": "frames", "command": ["/usr/bin/python3", "plugin.py"],
      "definition": {"weighting": "cosine"},
      "params": [{"name": "seed", "type": "integer", "default": 10, "min": 0, "max": 99,
                  "meaning": "m"},
                 {"name": "crash_at", "type": "integer", "default": -1, "min": -1, "max": 99,
                  "meaning": "m"}]})";
  // The program copies an AO image of the view's size (AOEVAL_TEST_AO) and logs each seed.
  std::ofstream(dir / "plugin.py") << R"(import json, os, shutil, signal, sys
with open('starts.txt', 'a') as f: f.write('start\n')
for line in sys.stdin:
    r = json.loads(line)
    p = json.load(open(r['params']))
    if r['frame'] == p['crash_at']:
        print('crashing at %d' % r['frame'], file=sys.stderr, flush=True)
        os.kill(os.getpid(), signal.SIGSEGV)
    with open('seeds.txt', 'a') as f: f.write('%d\n' % p['seed'])
    shutil.copy(os.environ['AOEVAL_TEST_AO'], r['out'])
    print(json.dumps({'frame': r['frame'], 'ok': True}), flush=True)
)";
  const std::string scene = static_sequence_scene();
  EvaluationSession session(ReferenceSpec{}, TimingSpec{0, 1}, false);
  // The image it copies: the built-in constant's estimate of this view, as aoeval writes it.
  {
    Measurement c = measure(session, scene, "constant", nlohmann::json::object());
    session.score(c, (dir / "ao.exr").string());
  }
  setenv("AOEVAL_TEST_AO", (dir / "ao.exr").c_str(), 1);
  add_plugin_dir(dir.string());
  for (const char* f : {"starts.txt", "seeds.txt"}) fs::remove(dir / f);
  Measurement m = measure(session, scene, "counting-frames", nlohmann::json::object());
  EXPECT_EQ(m.row.status, "ok");
  EXPECT_EQ(m.row.timing_source, "frame-wall");
  session.score(m);
  EXPECT_EQ(m.frames.size(), 8u);
  auto text = [&](const char* f) {
    std::ifstream in(dir / f);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(text("starts.txt"), "start\n") << "one program for the sequence point";
  EXPECT_EQ(text("seeds.txt"), "10\n11\n12\n13\n14\n15\n16\n17\n") << "the seed rule";
  Measurement crashed = measure(session, scene, "counting-frames", {{"crash_at", 3}});
  EXPECT_TRUE(crashed.frames.empty());
  EXPECT_EQ(crashed.row.status,
            "skipped: plug-in counting-frames killed by signal 11 (SEGV) before answering frame "
            "3: crashing at 3");
}

}  // namespace
}  // namespace aoeval
