// Test shader for the Vulkan layer (vulkan_test.cpp): a closed-form result from a push constant, a
// specialisation constant, a storage buffer and a storage image.
//   values_out[i] = scale * values_in[i] + OFFSET
//   image(x, y)   = scale * (x + 1000 * y) + OFFSET
#version 450
layout(local_size_x = 8, local_size_y = 8) in;

layout(constant_id = 0) const float OFFSET = 0.5;

layout(std430, set = 0, binding = 0) readonly buffer In { float values_in[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Out { float values_out[]; };
layout(set = 0, binding = 2, r32f) uniform writeonly image2D image;

layout(push_constant) uniform Push {
  float scale;
  uint count;
} pc;

void main() {
  const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 size = imageSize(image);
  if (xy.x >= size.x || xy.y >= size.y) return;
  imageStore(image, xy, vec4(pc.scale * float(xy.x + 1000 * xy.y) + OFFSET));
  const uint i = uint(xy.y * size.x + xy.x);
  if (i < pc.count) values_out[i] = pc.scale * values_in[i] + OFFSET;
}
