// The camera convention and the G-buffer, against closed forms (CONTRACT §3).
#include <gtest/gtest.h>

#include <pmmintrin.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {
namespace {

// A square of half-size `h` in the plane z = z0 (normal +Z when `front` is true, -Z otherwise).
SceneObject wall(float z0, float h, bool front) {
  SceneObject o;
  o.name = "wall";
  o.mesh.positions = {{-h, -h, z0}, {h, -h, z0}, {h, h, z0}, {-h, h, z0}};
  o.mesh.triangles = front ? std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}
                           : std::vector<glm::uvec3>{{0, 2, 1}, {0, 3, 2}};
  return o;
}

Scene scene_of(std::vector<SceneObject> objects) {
  Scene s;
  s.name = "test";
  s.objects = std::move(objects);
  View v;
  v.name = "main";
  v.eye = {0, 0, 0};
  v.target = {0, 0, -1};
  v.fov_y_deg = 60.0f;
  v.width = 64;
  v.height = 48;
  s.views = {v};
  return s;
}

TEST(GBuffer, PlaneAtKnownDistanceGivesExactDepthAndPixelCentres) {
  const float d = 3.0f;
  // Barycentric positions carry an error of a few float ulps of the triangle's extent, so the wall
  // is kept just larger than the view (half-size 10 -> ~5e-6) and the tolerance is 1e-5.
  Scene s = scene_of({wall(-d, 10.0f, true)});
  EmbreeScene es(s);
  Camera cam = make_camera(s.views[0]);
  GBuffer g = render_gbuffer(es, cam);
  const double t = std::tan(M_PI / 6.0), aspect = 64.0 / 48.0;
  for (int j = 0; j < g.height; ++j) {
    for (int i = 0; i < g.width; ++i) {
      const size_t k = g.index(i, j);
      ASSERT_EQ(g.coverage[k], 1.0f);
      EXPECT_NEAR(g.depth[k], d, 1e-5 * d);
      // Pixel centres (i + 0.5, j + 0.5), row 0 at the top.
      const double x = d * t * aspect * (2.0 * (i + 0.5) / 64.0 - 1.0);
      const double y = d * t * (1.0 - 2.0 * (j + 0.5) / 48.0);
      EXPECT_NEAR(g.position[k].x, x, 1e-5);
      EXPECT_NEAR(g.position[k].y, y, 1e-5);
      EXPECT_NEAR(g.position[k].z, -d, 1e-5);
      EXPECT_NEAR(g.normal[k].z, 1.0f, 1e-6);
      EXPECT_NEAR(g.geometric_normal[k].z, 1.0f, 1e-6);
      EXPECT_EQ(g.object_id[k], 0.0f);
    }
  }
  EXPECT_GT(g.position[g.index(0, 0)].y, 0.0f) << "row 0 is the top";
  EXPECT_LT(g.position[g.index(0, 0)].x, 0.0f) << "column 0 is the left";
}

TEST(GBuffer, FloorDepthFollowsTheRowFormula) {
  // Floor y = -1 facing up; below the horizon a pixel row j sees Z = 1 / (-y_j) with
  // y_j = tan(fov/2) (1 - 2 (j + 0.5) / H): depth depends on the row alone.
  SceneObject floor;
  floor.name = "floor";
  floor.mesh.positions = {{-50, -1, 50}, {50, -1, 50}, {50, -1, -50}, {-50, -1, -50}};
  floor.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  Scene s = scene_of({floor});
  EmbreeScene es(s);
  GBuffer g = render_gbuffer(es, make_camera(s.views[0]));
  const double t = std::tan(M_PI / 6.0);
  for (int j = 30; j < g.height; ++j) {
    const double yj = t * (1.0 - 2.0 * (j + 0.5) / 48.0);
    for (int i = 0; i < g.width; i += 7) {
      const size_t k = g.index(i, j);
      ASSERT_EQ(g.coverage[k], 1.0f);
      EXPECT_NEAR(g.depth[k], 1.0 / -yj, 1e-5 / -yj);
      EXPECT_NEAR(g.normal[k].y, 1.0f, 1e-6);
    }
  }
  for (int i = 0; i < g.width; ++i)
    EXPECT_EQ(g.coverage[g.index(i, 0)], 0.0f) << "sky is background";
}

TEST(GBuffer, BackFacingSurfacesAreFlippedToFaceTheViewer) {
  Scene s = scene_of({wall(-2.0f, 100.0f, false)});
  SceneObject& o = s.objects[0];
  o.mesh.normals.assign(4, glm::vec3(0, 0, -1));
  EmbreeScene es(s);
  GBuffer g = render_gbuffer(es, make_camera(s.views[0]));
  const size_t k = g.index(10, 10);
  EXPECT_NEAR(g.geometric_normal[k].z, 1.0f, 1e-6);
  EXPECT_NEAR(g.normal[k].z, 1.0f, 1e-6);
}

TEST(GBuffer, ObjectIdsAndBackground) {
  Scene s = scene_of({wall(-2.0f, 0.5f, true), wall(-5.0f, 100.0f, true)});
  s.objects[1].name = "back";
  EmbreeScene es(s);
  GBuffer g = render_gbuffer(es, make_camera(s.views[0]));
  EXPECT_EQ(g.object_id[g.index(32, 24)], 0.0f);
  EXPECT_EQ(g.object_id[g.index(0, 0)], 1.0f);
}

TEST(GBuffer, DeterministicAndRoundTripsThroughExr) {
  Scene s = scene_of({wall(-3.0f, 100.0f, true)});
  EmbreeScene es(s);
  Camera cam = make_camera(s.views[0], 37, 23);
  GBuffer a = render_gbuffer(es, cam), b = render_gbuffer(es, cam);
  EXPECT_EQ(a.depth, b.depth);
  const std::string path = (aoeval::testutil::test_temp_dir("gbuffer") / "rt.exr").string();
  write_exr(path, gbuffer_to_image(a), gbuffer_attributes(s, s.views[0], cam));
  GBuffer r = read_gbuffer(path);
  EXPECT_EQ(r.width, 37);
  EXPECT_EQ(r.height, 23);
  EXPECT_EQ(r.depth, a.depth);
  EXPECT_EQ(r.object_id, a.object_id);
  EXPECT_NEAR(r.camera.tan_half_fov_y, cam.tan_half_fov_y, 1e-6);
  EXPECT_NEAR(r.camera.forward.z, -1.0f, 1e-6);
  std::filesystem::remove(path);
}

// Non-finite motion on a covered pixel is damaged input (a NaN offset crashed the temporal scorer,
// an infinite one passed as "off screen"): read_gbuffer refuses it naming the file, the channel
// and the pixel. On an uncovered pixel nothing reads it.
TEST(GBuffer, NonFiniteMotionOnACoveredPixelIsRefusedNamingFileAndPixel) {
  Scene s = scene_of({wall(-3.0f, 100.0f, true)});
  EmbreeScene es(s);
  const Camera cam = make_camera(s.views[0], 8, 6);
  const std::string path = (aoeval::testutil::test_temp_dir("gbuffer") / "motion.exr").string();
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  struct Case {
    int channel;  // 0 motion.X, 1 motion.Y, 2 disoccluded
    float value;
    const char* expected;
  };
  for (const Case& c : {Case{0, nan, "motion.X is NaN at covered pixel (5, 2)"},
                        Case{1, inf, "motion.Y is inf at covered pixel (5, 2)"},
                        Case{0, -inf, "motion.X is -inf at covered pixel (5, 2)"},
                        Case{2, nan, "disoccluded is NaN at covered pixel (5, 2)"}}) {
    GBuffer g = render_gbuffer(es, cam);
    g.motion.assign(g.pixel_count(), glm::vec2(0.5f, -0.25f));
    g.disoccluded.assign(g.pixel_count(), 0.0f);
    const size_t k = g.index(5, 2);
    ASSERT_TRUE(g.covered(k));
    if (c.channel == 2)
      g.disoccluded[k] = c.value;
    else
      g.motion[k][c.channel] = c.value;
    write_exr(path, gbuffer_to_image(g), gbuffer_attributes(s, s.views[0], cam));
    try {
      read_gbuffer(path);
      ADD_FAILURE() << c.expected << ": read";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": " + c.expected, 0), 0u) << e.what();
    }
    // The same value where nothing is covered is not read by anyone.
    g.coverage[k] = 0.0f;
    write_exr(path, gbuffer_to_image(g), gbuffer_attributes(s, s.views[0], cam));
    EXPECT_EQ(read_gbuffer(path).motion.size(), g.pixel_count());
  }
  std::filesystem::remove(path);
}

// Embree asks for flush-to-zero and denormals-are-zero on every thread that traces. TBB's worker
// threads have usually run other loops (a scene load's) before the first trace, under the
// floating-point settings TBB captured then; every task of a tracing loop must still have the
// flags, or a denormal would be flushed on some threads and not on others, and results would
// depend on which thread took which pixel.
TEST(EmbreeThreads, EveryTaskOfATracingLoopFlushesDenormals) {
  auto slow = [] { std::this_thread::sleep_for(std::chrono::milliseconds(1)); };
  tbb::parallel_for(0, 64, 1, [&](int) { slow(); });  // the workers start without the flags
  const unsigned control_bits = ~0x3Fu;  // not the sticky exception flags, which any code may set
  const unsigned caller = _mm_getcsr() & control_bits;
  std::atomic<int> with_flags{0};
  parallel_for_embree(tbb::blocked_range<int>(0, 64, 1), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i < r.end(); ++i) {
      slow();
      with_flags += _MM_GET_FLUSH_ZERO_MODE() == _MM_FLUSH_ZERO_ON &&
                    _MM_GET_DENORMALS_ZERO_MODE() == _MM_DENORMALS_ZERO_ON;
    }
  });
  EXPECT_EQ(with_flags.load(), 64) << "iterations of 64 ran with FTZ and DAZ on";
  EXPECT_EQ(_mm_getcsr() & control_bits, caller)
      << "the caller's own settings are left as they were";
}

}  // namespace
}  // namespace aoeval
