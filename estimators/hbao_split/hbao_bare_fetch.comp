// The baseline of `aoeval bench hbao`: nothing but nearest-texel depth fetches, walks x steps per
// pixel along screen-space walks (hbao-split's access pattern without its arithmetic), summed and
// stored so that the compiler keeps every fetch.
#version 450
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D sum_image;
layout(std430, set = 0, binding = 2) readonly buffer Walks { vec2 walk_steps[]; };  // pixels

layout(push_constant) uniform Push {
  int width;
  int height;
  int walks;
  int steps;
} pc;

void main() {
  ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
  if (xy.x >= pc.width || xy.y >= pc.height) return;
  vec2 origin = vec2(xy) + vec2(0.5);
  ivec2 last = ivec2(pc.width - 1, pc.height - 1);
  float sum = 0.0;
  for (int w = 0; w < pc.walks; ++w) {
    vec2 step = walk_steps[w];
    for (int s = 1; s <= pc.steps; ++s) {
      ivec2 p = clamp(ivec2(origin + step * float(s)), ivec2(0), last);
      sum += imageLoad(depth_image, p).r;
    }
  }
  imageStore(sum_image, xy, vec4(sum));
}
