// gtao pass 1: the horizons of every slice, the closed-form integrals (AO and bent normal).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "gtao_common.glsl"

void main() {
  ivec2 xy = gtao_invocation_pixel();
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  vec3 bent;
  float ao = gtao_pixel(xy.x, xy.y, pc.c, bent);
  imageStore(raw_ao_image, xy, vec4(ao));
  imageStore(raw_bent_image, xy, vec4(bent, 0.0f));
}
