// ReferenceStore's FLIP frame sides (flip_frame_reference, issue 42): shared by key, and bounded so
// that the sides another scoring reused outlive those never reused.
#include <gtest/gtest.h>

#include "harness/evaluation/reference_store.h"

namespace aoeval {
namespace {

TEST(ReferenceStore, FlipFrameSidesAreSharedAndThoseNeverReusedGoFirst) {
  // 2000x1000 pixels: about 194 MB a side, so the third side passes kFlipFramesBytes (512 MiB).
  const int w = 2000, h = 1000;
  GBuffer g;
  g.width = w;
  g.height = h;
  g.coverage.assign(g.pixel_count(), 1.0f);
  ReferenceImage ref;
  ref.width = w;
  ref.height = h;
  ref.ao.assign(g.pixel_count(), 0.5f);
  ref.coverage = g.coverage;
  StageTimes stages;
  SceneCache scenes(stages);
  ReferenceStore store(ReferenceSpec{}, false, scenes, stages);
  const auto a = store.flip_frame_reference("true-ao frame 0", g, ref);
  EXPECT_EQ(store.flip_frame_reference("true-ao frame 0", g, ref), a) << "shared by key";
  const auto b = store.flip_frame_reference("matched frame 0", g, ref);  // never reused
  const auto c = store.flip_frame_reference("true-ao frame 1", g, ref);  // past the bound
  // The oldest, a, was reused: b goes instead.
  EXPECT_EQ(store.flip_frame_reference("true-ao frame 0", g, ref), a);
  EXPECT_EQ(store.flip_frame_reference("true-ao frame 1", g, ref), c);
  EXPECT_NE(store.flip_frame_reference("matched frame 0", g, ref), b) << "prepared again";
  EXPECT_EQ(b->filtered, a->filtered);  // the same image, the same side
}

}  // namespace
}  // namespace aoeval
