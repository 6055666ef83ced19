// gtao pass 2: the spatial denoise over one period of the noise (§5.2).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "gtao_common.glsl"

void main() {
  ivec2 xy = gtao_invocation_pixel();
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  vec3 bent;
  float ao = gtao_denoise(xy.x, xy.y, pc.c, bent);
  imageStore(ao_image, xy, vec4(ao));
  imageStore(bent_image, xy, vec4(bent, 0.0f));
}
