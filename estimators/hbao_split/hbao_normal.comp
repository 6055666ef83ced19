// hbao-split pass 2, normal occlusion above the horizons (§3.3) and A = 1 - (O_T + O_N) (§3.4).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "hbao_common.glsl"

void main() {
  ivec2 xy = hbao_invocation_pixel();
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  float ot = imageLoad(ot_image, xy).r;
  imageStore(raw_ao_image, xy, vec4(hbao_normal_pass(xy.x, xy.y, ot, pc.c)));
}
