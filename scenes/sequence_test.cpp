// Sequences (CONTRACT §10): the scene format's keyframes and their validation, and the G-buffer's
// exact motion vectors and disocclusion on scenes with a known answer.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include "base/errors.h"
#include "base/testing/test_temp_dir.h"
#include "scenes/embree_scene.h"
#include "scenes/scene.h"
#include "scenes/sequence_frame.h"

namespace aoeval {
namespace {

std::string write_scene(const std::string& name, const std::string& sequence) {
  const auto dir = testutil::test_temp_dir("sequence");
  const std::string path = (dir / name).string();
  std::ofstream(path)
      << R"({"objects": [{"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
     {"name": "box", "generator": "box", "params": {"size": [0.5, 0.5, 0.5]}}],
    "views": [{"name": "walk", "eye": [0, 1, 3], "target": [0, 0, 0], "sequence": )"
      << sequence << "}]}";
  return path;
}

std::string load_error(const std::string& sequence) {
  try {
    load_scene_file(write_scene("s.json", sequence));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Sequence, ParsesKeysAndInterpolatesLinearly) {
  const Scene s = load_scene_file(write_scene("ok.json", R"({"frames": 11, "fps": 24,
      "camera": [{"frame": 10, "eye": [2, 1, 3], "target": [0, 0, 0]}],
      "objects": {"box": [{"frame": 0}, {"frame": 10, "translate": [1, 0, 0], "rotate_deg": [0, 90, 0]}]}})"));
  const View& v = s.views[0];
  ASSERT_TRUE(v.sequence);
  EXPECT_EQ(v.frame_count(), 11);
  EXPECT_DOUBLE_EQ(v.sequence->fps, 24.0);
  // The view's own camera is frame 0's; linear to the key at frame 10, held after it.
  const CameraKey c5 = camera_at(*v.sequence, v.eye, v.target, 5);
  EXPECT_FLOAT_EQ(c5.eye.x, 1.0f);
  EXPECT_FLOAT_EQ(camera_at(*v.sequence, v.eye, v.target, 0).eye.x, 0.0f);
  const ObjectKey k5 = object_key_at(*v.sequence, "box", 5);
  EXPECT_FLOAT_EQ(k5.translate.x, 0.5f);
  EXPECT_FLOAT_EQ(k5.rotate_deg.y, 45.0f);
  EXPECT_FLOAT_EQ(k5.scale.y, 1.0f);
  // A frame's posed scene moves the box and only the box; frame 0 is the scene as placed.
  const SequenceFrame f10 = sequence_frame(s, v, 10);
  EXPECT_TRUE(f10.moves_objects);
  const Scene posed = posed_scene(s, f10);
  EXPECT_NEAR(posed.objects[1].mesh.bounds().center().x, s.objects[1].mesh.bounds().center().x + 1,
              1e-5);
  EXPECT_EQ(posed.objects[0].mesh.positions, s.objects[0].mesh.positions);
  EXPECT_FALSE(sequence_frame(s, v, 0).moves_objects);
  EXPECT_NE(posed.content_hash(), s.content_hash());
  EXPECT_THROW(sequence_frame(s, v, 11), InputError);
}

TEST(Sequence, ErrorsNameTheField) {
  EXPECT_NE(load_error(R"({"frames": 4, "speed": 2})").find("sequence.speed"), std::string::npos);
  EXPECT_NE(
      load_error(R"({"frames": 4, "camera": [{"frame": 4, "eye": [1,1,1], "target": [0,0,0]}]})")
          .find("camera[0].frame"),
      std::string::npos);
  EXPECT_NE(load_error(R"({"frames": 4, "objects": {"dragon": [{"frame": 0}]}})")
                .find("no object named 'dragon'"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"frames": 4, "objects": {"box": [{"frame": 2}, {"frame": 1}]}})")
                .find("increasing frame order"),
            std::string::npos);
  EXPECT_NE(
      load_error(R"({"frames": 4, "camera": [{"frame": 0, "eye": [1,1,1], "target": [0,0,0]}]})")
          .find("view's own eye"),
      std::string::npos);
  EXPECT_NE(load_error(R"({"frames": 4, "jitter": "random"})").find("sequence.jitter"),
            std::string::npos);
  EXPECT_NE(load_error(R"({"frames": 0})").find("sequence.frames"), std::string::npos);
  // The views alone (sweep planning) check object names too.
  EXPECT_THROW(
      load_scene_views(write_scene("v.json", R"({"frames": 2, "objects": {"x": [{"frame": 0}]}})")),
      InputError);
}

// Every frame's camera is checked when the scene loads, not only the keys: a path through its
// target, or one that looks along `up` between two good keys, loaded, rendered frame 0 and stopped
// a sweep at the bad frame with a line naming nothing.
TEST(Sequence, ACameraPathThatDegeneratesBetweenKeysIsRefusedNamingViewAndFrame) {
  const std::string through = write_scene(
      "through.json",
      R"({"frames": 5, "camera": [{"frame": 4, "eye": [0, -1, -3], "target": [0, 0, 0]}]})");
  const std::string along_up = write_scene(
      "along_up.json",
      R"({"frames": 9, "camera": [{"frame": 8, "eye": [0, 1, -3], "target": [0, 0, 0]}]})");
  for (const auto& [path, expected] : std::vector<std::pair<std::string, std::string>>{
           {through, "view 'walk', frame 2 (between the keys): eye and target coincide"},
           {along_up,
            "view 'walk', frame 4 (between the keys): up is parallel to the viewing direction"}}) {
    SCOPED_TRACE(path);
    for (const bool views_only : {false, true}) {
      try {
        if (views_only)
          load_scene_views(path);
        else
          load_scene_file(path);
        ADD_FAILURE() << "loaded";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
        EXPECT_NE(what.find("sequence.camera: " + expected), std::string::npos) << what;
      }
    }
  }
}

TEST(Sequence, HaltonJitterStaysInsideThePixel) {
  Sequence s;
  s.frames = 32;
  s.jitter = Jitter::halton;
  EXPECT_FLOAT_EQ(frame_jitter(s, 0).x, 0.0f);  // Halton(1, 2) = 1/2
  EXPECT_FLOAT_EQ(frame_jitter(s, 1).x, -0.25f);
  EXPECT_EQ(frame_jitter(s, 3), frame_jitter(s, 19));  // a 16-frame cycle
  for (int k = 0; k < 16; ++k) {
    EXPECT_LT(std::abs(frame_jitter(s, k).x), 0.5f);
    EXPECT_LT(std::abs(frame_jitter(s, k).y), 0.5f);
  }
  s.jitter = Jitter::none;
  EXPECT_EQ(frame_jitter(s, 5), glm::vec2(0.0f));
}

// An axis-aligned rectangle in the plane z = `z`, facing +z.
SceneObject rectangle(const std::string& name, float x0, float x1, float y0, float y1, float z) {
  SceneObject o;
  o.name = name;
  o.mesh.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  o.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return o;
}

View still_view(int w, int h) {
  View v;
  v.name = "v";
  v.eye = glm::vec3(0.0f);
  v.target = glm::vec3(0, 0, -1);
  v.fov_y_deg = 60.0f;
  v.width = w;
  v.height = h;
  return v;
}

struct Frames {
  GBuffer g0, g1;
};

Frames render_two(const Scene& scene, const View& view) {
  const SequenceFrame f0 = sequence_frame(scene, view, 0), f1 = sequence_frame(scene, view, 1);
  const Scene s0 = posed_scene(scene, f0), s1 = posed_scene(scene, f1);
  const EmbreeScene e0(s0), e1(s1);
  Frames f{render_gbuffer(e0, frame_camera(f0)), render_gbuffer(e1, frame_camera(f1))};
  add_motion(f.g0, nullptr, f0.motion, f0.motion);
  add_motion(f.g1, &f.g0, f1.motion, f0.motion);
  return f;
}

// Must-show 2: a camera translating sideways by dx over a fronto-parallel plane at depth z moves
// every point by f dx / z pixels, f = height / (2 tan(fov/2)); to the left when the camera moves
// right, so motion.X (now minus then) is -f dx / z.
TEST(SequenceMotion, SidewaysCameraOverAPlaneMovesByFocalTimesShiftOverDepth) {
  const float z = 3.0f, dx = 0.05f;
  Scene scene;
  scene.objects.push_back(rectangle("wall", -20, 20, -20, 20, -z));
  View view = still_view(80, 60);
  Sequence seq;
  seq.frames = 2;
  seq.camera = {{0, view.eye, view.target}, {1, glm::vec3(dx, 0, 0), glm::vec3(dx, 0, -1)}};
  view.sequence = seq;
  scene.views = {view};
  const Frames f = render_two(scene, view);
  const double focal = 60.0 / (2.0 * std::tan(glm::radians(30.0)));
  const double expected = -focal * dx / z;
  size_t checked = 0;
  for (size_t k = 0; k < f.g1.pixel_count(); ++k) {
    ASSERT_TRUE(f.g1.covered(k));
    EXPECT_NEAR(f.g1.motion[k].x, expected, 1e-3) << "pixel " << k;
    EXPECT_NEAR(f.g1.motion[k].y, 0.0, 1e-3);
    // Off screen in frame 0 only in the strip the camera moved into.
    const int i = static_cast<int>(k % f.g1.width);
    EXPECT_EQ(f.g1.disoccluded[k] > 0.5f, i + 0.5 - expected >= f.g1.width) << "pixel " << k;
    ++checked;
  }
  EXPECT_EQ(checked, 80u * 60u);
  for (size_t k = 0; k < f.g0.pixel_count(); ++k) EXPECT_EQ(f.g0.motion[k], glm::vec2(0.0f));
}

// Must-show 2: an object moving in front of a wall (static camera) leaves `disoccluded` exactly on
// the strip of wall it uncovers: pixels that saw the object in frame 0 and see the wall in frame 1.
TEST(SequenceMotion, ObjectMovingInFrontOfAWallDisoccludesExactlyTheUncoveredStrip) {
  const int w = 64, h = 48;
  const float z = 2.0f, shift_px = 6.0f;
  const double half_w = z * std::tan(glm::radians(30.0)) * w / h;  // half the image width at z
  auto world_x = [&](double px) { return static_cast<float>((2.0 * px / w - 1.0) * half_w); };
  // Edges a quarter pixel off the pixel centres, so every centre is clearly in or out.
  Scene scene;
  scene.objects.push_back(rectangle("wall", -20, 20, -20, 20, -4));
  scene.objects.push_back(rectangle("card", world_x(20.25), world_x(40.25), -0.5f, 0.5f, -z));
  View view = still_view(w, h);
  Sequence seq;
  seq.frames = 2;
  const float dx = world_x(shift_px) - world_x(0);
  seq.objects["card"] = {{0}, {1, glm::vec3(dx, 0, 0)}};
  view.sequence = seq;
  scene.views = {view};
  const Frames f = render_two(scene, view);
  size_t strip = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const size_t k = f.g1.index(i, j);
      const bool card_then = f.g0.object_id[k] == 1.0f, card_now = f.g1.object_id[k] == 1.0f;
      const bool uncovered = card_then && !card_now;
      // The analytic strip: columns 20..25 of the card's rows.
      const bool in_strip = i >= 20 && i < 26 && card_then;
      EXPECT_EQ(uncovered, in_strip) << i << "," << j;
      EXPECT_EQ(f.g1.disoccluded[k] > 0.5f, uncovered) << i << "," << j;
      if (card_now)
        EXPECT_NEAR(f.g1.motion[k].x, shift_px, 1e-3);
      else
        EXPECT_NEAR(f.g1.motion[k].x, 0.0, 1e-3);
      strip += uncovered;
    }
  EXPECT_GT(strip, 6u * 10u);
}

}  // namespace
}  // namespace aoeval
