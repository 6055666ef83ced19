// The screen-space frame's normals: a world-space unit normal in eye space (the camera's right, up,
// forward axes), renormalised; a zero normal gives (0, 0, -1), facing the eye. Both routes to a
// frame convert with this text, the host from the Embree G-buffer (frame.cpp, as C++ through
// glsl_compat.h) and the device from the raster one (eye_normals.comp), so they see the same bits.
float eye_dot(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

vec3 eye_normal(vec3 n, vec3 right, vec3 up, vec3 forward) {
  vec3 e = vec3(eye_dot(n, right), eye_dot(n, up), eye_dot(n, forward));
  precise float len = sqrt(eye_dot(e, e));
  if (!(len > 0.0f)) return vec3(0.0f, 0.0f, -1.0f);
  precise vec3 unit = e / len;
  return unit;
}
