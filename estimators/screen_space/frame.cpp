// The screen-space frame on the host (frame.h). The normal conversion is eye_normal.glsl, compiled
// here as C++ through glsl_compat.h, the text the raster route's eye_normals.comp runs.
#include "estimators/screen_space/frame.h"

#include <cmath>
#include <numeric>

#include "estimators/screen_space/glsl_compat.h"

namespace aoeval::glsl::frame {
#include "estimators/screen_space/eye_normal.glsl"
}  // namespace aoeval::glsl::frame

#include "estimators/screen_space/glsl_compat_end.h"

namespace aoeval {

ScreenSpaceFrame screen_space_frame_shape(const Camera& camera) {
  ScreenSpaceFrame f;
  f.width = camera.width;
  f.height = camera.height;
  f.focal = static_cast<float>(camera.height) / (2.0f * camera.tan_half_fov_y);
  return f;
}

ScreenSpaceFrame screen_space_frame_from_gbuffer(const GBuffer& g) {
  ScreenSpaceFrame f = screen_space_frame_shape(g.camera);
  f.depth.assign(g.pixel_count(), 0.0f);
  f.normal.assign(g.pixel_count(), glm::vec3(0.0f, 0.0f, -1.0f));
  const Camera& c = g.camera;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    if (!g.covered(k) || !(g.depth[k] > 0.0f)) continue;
    f.depth[k] = g.depth[k];
    f.normal[k] = glsl::frame::eye_normal(g.normal[k], c.right, c.up, c.forward);
  }
  return f;
}

int workgroup_row_stride(int rows) {
  if (rows <= 2) return 1;
  const auto golden = static_cast<int>(std::lround(rows * 0.6180339887498949));
  for (int offset = 0;; ++offset) {
    for (const int s : {golden - offset, golden + offset})
      if (s >= 1 && s < rows && std::gcd(s, rows) == 1) return s;
  }
}

}  // namespace aoeval
