// The constants of the horizon-split kernel (hbao_kernel.glsl), shared text as well: C++ includes
// it inside namespace aoeval::hbao_glsl (hbao_split.h), the shaders include it before the kernel.
// Every member is a 4-byte scalar, so the C++ struct and the GLSL push-constant block share one
// layout.
struct HbaoConstants {
  float radius;        // R, scene units (§3.6)
  float step;          // R / Ns: the step of the linear searches (Fig. 4 line 3, §4.1.2)
  float focal;         // f = H / (2 tan(fov_y / 2)), pixels (hbao_kernel.glsl)
  float half_width;    // W / 2
  float half_height;   // H / 2
  float offset_scale;  // eq. 13: P' = P + z / (f res) n; 1 / (f res) = 1 / (2 focal), 0 = off
  int width;
  int height;
  int directions;   // Nd
  int steps;        // Ns
  int normal_rays;  // Nn
  int attenuation;  // 1: linear attenuation of §3.5, 0: none
  int tile;         // side of the tiled random texture, pixels (§4.1.2)
  int row_stride;   // the shaders' workgroup row order (hbao_common.glsl); the CPU twin ignores it
};
