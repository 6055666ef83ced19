// SceneCache::posed_frame() (issue 42): a sequence frame posed and rendered once for every point of
// its view is the frame that `aoeval gbuffer --frame K` renders on its own, channel for channel.
#include "harness/evaluation/scene_cache.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "base/testing/test_temp_dir.h"

namespace aoeval {
namespace {

// A box sliding and turning on a floor while the camera moves, 5 frames at 64x48.
std::string moving_scene() {
  const auto dir = testutil::test_temp_dir("scene_cache");
  const std::string path = (dir / "moving.json").string();
  std::ofstream(path) << R"({"objects": [
      {"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
      {"name": "box", "generator": "box", "params": {"size": [0.6, 0.6, 0.6]},
       "transform": {"translate": [0, 0.3, 0]}}],
    "views": [{"name": "move", "eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0], "fov_y_deg": 50,
               "width": 64, "height": 48, "sequence": {"frames": 5, "fps": 30,
      "camera": [{"frame": 0, "eye": [0.9, 1.4, 1.3], "target": [0, 0.1, 0]},
                 {"frame": 4, "eye": [1.1, 1.3, 1.0], "target": [0.1, 0.1, 0]}],
      "objects": {"box": [{"frame": 0, "translate": [0, 0, 0]},
                          {"frame": 4, "translate": [0.4, 0, 0], "rotate_deg": [0, 30, 0]}]}}}]})";
  return path;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(SceneCache, AKeptSequenceFrameIsTheFrameRenderedAlone) {
  StageTimes stages;
  SceneCache cache(stages);
  const std::string scene = moving_scene();
  const Scene& base = cache.scene(scene).scene;
  const View& view = base.view("move");
  std::vector<std::shared_ptr<const PosedFrame>> first;
  for (int k = 0; k < 5; ++k) {
    first.push_back(cache.posed_frame(scene, view, k, 64, 48, k ? first.back().get() : nullptr));
    const PosedFrame& f = *first.back();
    const GBuffer alone = render_frame_gbuffer(base, view, k, 64, 48);
    const GBuffer& g = *f.gbuffer;
    EXPECT_TRUE(same_bits(g.coverage, alone.coverage)) << k;
    EXPECT_TRUE(same_bits(g.depth, alone.depth)) << k;
    EXPECT_TRUE(same_bits(g.position, alone.position)) << k;
    EXPECT_TRUE(same_bits(g.normal, alone.normal)) << k;
    EXPECT_TRUE(same_bits(g.object_id, alone.object_id)) << k;
    EXPECT_TRUE(same_bits(g.motion, alone.motion)) << k;
    EXPECT_TRUE(same_bits(g.disoccluded, alone.disoccluded)) << k;
    EXPECT_EQ(g.camera.jitter, alone.camera.jitter) << k;
    ASSERT_EQ(f.posed != nullptr, k > 0) << "frame 0's box is where the scene has it";
    if (f.posed) {
      EXPECT_EQ(f.posed->content_hash,
                posed_scene(base, sequence_frame(base, view, k)).content_hash());
    }
  }
  // A later point of the view gets the same frames, rendered and posed once.
  const double rendered_ms = stages.ms("G-buffer");
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(cache.posed_frame(scene, view, k, 64, 48, k ? first[k - 1].get() : nullptr),
              first[k]);
  EXPECT_EQ(stages.ms("G-buffer"), rendered_ms);
}

}  // namespace
}  // namespace aoeval
