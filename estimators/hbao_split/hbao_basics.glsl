// The kernel's smallest shared pieces (see hbao_kernel.glsl), separate so that the raster path's
// normal conversion (hbao_eye_normals.comp) can include them without the rest.
float hbao_dot(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

// A world-space unit normal in eye space (the camera's right, up, forward axes), renormalised; a
// zero normal gives (0, 0, -1), facing the eye. Both twins convert with this function (the CPU from
// the Embree G-buffer, the GPU from the raster one), so they see the same bits.
vec3 hbao_eye_normal(vec3 n, vec3 right, vec3 up, vec3 forward) {
  vec3 e = vec3(hbao_dot(n, right), hbao_dot(n, up), hbao_dot(n, forward));
  precise float len = sqrt(hbao_dot(e, e));
  if (!(len > 0.0f)) return vec3(0.0f, 0.0f, -1.0f);
  precise vec3 unit = e / len;
  return unit;
}
