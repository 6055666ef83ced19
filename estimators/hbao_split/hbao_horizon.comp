// hbao-split pass 1, horizon occlusion (§3.1-3.2): O_T per pixel and H(theta_d) per direction.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "hbao_common.glsl"

void main() {
  ivec2 xy = hbao_invocation_pixel();
  if (xy.x >= pc.c.width || xy.y >= pc.c.height) return;
  imageStore(ot_image, xy, vec4(hbao_horizon_pass(xy.x, xy.y, pc.c)));
}
