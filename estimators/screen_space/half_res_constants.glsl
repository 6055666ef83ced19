// The constants of the half-resolution passes (half_res.glsl), shared text: C++ includes it inside
// namespace aoeval::half_res_glsl (half_res.h), the shaders before the kernel. Every member is a
// 4-byte scalar, so the C++ struct and the GLSL push-constant block share one layout.
struct HalfResConstants {
  int width;        // the full-resolution frame, pixels
  int height;
  int low_width;    // the half-resolution frame: ceil(width / 2)
  int low_height;   // ceil(height / 2)
  int vector;       // 1: the upsample pass also upsamples the vector image (gtao's bent normals)
};
