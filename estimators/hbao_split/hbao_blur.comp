// hbao-split pass 3, the depth-aware 5x5 blur (§4.1.3).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "hbao_common.glsl"

void main() {
  ivec2 xy = hbao_invocation_pixel();
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  imageStore(ao_image, xy, vec4(hbao_blur(xy.x, xy.y, pc.c)));
}
