// The per-step test of Fig. 4 in the shared kernel (hbao_kernel.glsl, compiled here as C++ the way
// the CPU twin compiles it): ISBELOW(Q, S) and the screen-scaled points it takes.
#include <gtest/gtest.h>

#include <vector>

#include "estimators/hbao_split/hbao_cpu_kernel.h"

namespace aoeval::hbao_glsl {
namespace kernel_test {
// Every fetch must land inside the image, whatever the point: the kernel clamps the address
// instead of selecting it, and a read outside would be out of bounds on the CPU twin.
int out_of_bounds_fetches = 0;
inline float hbao_depth(const HbaoImages& img, int i, int j) {
  if (i < 0 || j < 0 || i >= img.width || static_cast<size_t>(j) * img.width >= img.pixels) {
    ++out_of_bounds_fetches;
    return 0.0f;
  }
  return img.depth[pixel_of(img, i, j)];
}
#include "estimators/hbao_split/hbao_kernel.glsl"
}  // namespace kernel_test
}  // namespace aoeval::hbao_glsl

#include "estimators/hbao_split/hbao_cpu_kernel_end.h"

namespace aoeval::hbao_glsl {
namespace {

// A 4x3 image: a surface at depth 1 everywhere except background (0) at pixel (3, 2).
struct Fixture {
  std::vector<float> depth = std::vector<float>(12, 1.0f);
  HbaoImages images;
  HbaoConstants c{};
  Fixture() {
    depth[2 * 4 + 3] = 0.0f;
    images.width = 4;
    images.pixels = depth.size();
    images.depth = depth.data();
    c.width = 4;
    c.height = 3;
    c.focal = 2.0f;
    c.half_width = 2.0f;
    c.half_height = 1.5f;
  }
  // The eye-space point seen through image position (u, v) (pixel units, continuous) at depth d.
  vec3 eye_point(float u, float v, float d) const {
    return vec3((u - c.half_width) / c.focal * d, (c.half_height - v) / c.focal * d, d);
  }
  bool below(vec3 q, float& z, float& inv_z) const {
    return kernel_test::hbao_below(images, kernel_test::hbao_screen(q, c), c, z, inv_z);
  }
};

TEST(HbaoKernel, ScreenScaledPointsProjectToTheirPixel) {
  const Fixture f;
  for (const float d : {0.5f, 2.0f, 7.0f}) {
    const vec3 s = kernel_test::hbao_screen(f.eye_point(1.25f, 2.5f, d), f.c);
    EXPECT_NEAR(s.x / s.z, 1.25f, 1e-5f);
    EXPECT_NEAR(s.y / s.z, 2.5f, 1e-5f);
    EXPECT_EQ(s.z, d);
  }
}

TEST(HbaoKernel, BelowOnlyInsideTheScreenAndBehindTheSurface) {
  Fixture f;
  kernel_test::out_of_bounds_fetches = 0;
  float z = 0.0f, inv_z = 0.0f;
  // Inside, behind the surface at depth 1: below, with the texel's depth and 1 / Q.z.
  EXPECT_TRUE(f.below(f.eye_point(1.5f, 1.5f, 10.0f), z, inv_z));
  EXPECT_EQ(z, 1.0f);
  EXPECT_FLOAT_EQ(inv_z, 0.1f);
  // In front of the surface, or over background: not below.
  EXPECT_FALSE(f.below(f.eye_point(1.5f, 1.5f, 0.5f), z, inv_z));
  EXPECT_FALSE(f.below(f.eye_point(3.5f, 2.5f, 10.0f), z, inv_z));
  // Off the screen on every side, although the clamped fetch reads a surface texel in front of
  // the point (u in (-1, 0) truncates to column 0; u beyond int's range): not below.
  for (const auto& [u, v] : std::vector<std::pair<float, float>>{{-0.5f, 1.5f},
                                                                 {-7.0f, 1.5f},
                                                                 {4.0f, 1.5f},
                                                                 {9.5f, 1.5f},
                                                                 {1.5f, -0.25f},
                                                                 {1.5f, 3.0f},
                                                                 {-3.0f, 8.0f}}) {
    EXPECT_FALSE(f.below(f.eye_point(u, v, 10.0f), z, inv_z)) << "u " << u << " v " << v;
  }
  // Behind the eye (Q.z <= 0) projects anywhere; not below.
  EXPECT_FALSE(f.below(vec3(0.1f, 0.1f, -10.0f), z, inv_z));
  EXPECT_FALSE(f.below(vec3(0.1f, 0.1f, 0.0f), z, inv_z));
  EXPECT_EQ(kernel_test::out_of_bounds_fetches, 0);
}

}  // namespace
}  // namespace aoeval::hbao_glsl
