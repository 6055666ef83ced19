// The constants of the GTAO kernel (gtao_kernel.glsl), shared text: C++ includes it inside
// namespace aoeval::gtao_glsl (gtao.h), the shaders include it before the kernel. Every member is a
// 4-byte scalar, so the C++ struct and the GLSL push-constant block share one layout.
struct GtaoConstants {
  float radius;        // R, scene units: dmax of the declared definition
  float falloff_mul;   // 1 / (falloff R): weight (R - d) falloff_mul, clamped to [0, 1]
  float thickness;     // thin-occluder compensation: how far a lower sample pulls the horizon down
  float focal;         // f = H / (2 tan(fov_y / 2)), pixels
  float half_width;    // W / 2
  float half_height;   // H / 2
  float radius_scale;  // R f: the screen radius at depth z is radius_scale / z pixels
  int width;
  int height;
  int slices;     // slice directions per pixel
  int steps;      // samples per side of each slice
  int tile;       // side of the tiled noise texture, pixels
  int normalise;  // 1: divide by the same slice sum over the unoccluded hemisphere
  int row_stride; // the shaders' workgroup row order (as hbao's); the CPU twin ignores it
};
