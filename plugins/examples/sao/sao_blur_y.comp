#version 450
// Scalable Ambient Obscurance's reconstruction filter, the vertical half: a 9-tap Gaussian with
// stride 2 pixels (the paper's R = 4, scale 2), each tap's weight multiplied by
// max(0, 1 - edge_sharpness * 100 |z_tap - z| / z) so that it does not blur across depth edges.
// The paper keys the weight on depth normalised by the far plane; aoeval's projection has none, so
// the difference is taken relative to the pixel's depth (1 % of it zeroes the weight at sharpness
// 1). Reads the previous pass's output (aoeval_prev), writes aoeval_out.
layout(local_size_x = 8, local_size_y = 8) in;

const float kGaussian[5] = float[](0.153170, 0.144893, 0.122649, 0.092902, 0.058858);
const ivec2 kAxis = ivec2(0, 1);

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!aoeval_inside(p)) return;
  const float a = imageLoad(aoeval_prev, p).r;
  if (!aoeval.params.blur || !aoeval_covered(p)) {
    imageStore(aoeval_out, p, vec4(a));
    return;
  }
  const float z = imageLoad(aoeval_depth, p).r;
  float sum = a * kGaussian[0], total = kGaussian[0];
  for (int t = -4; t <= 4; ++t) {
    if (t == 0) continue;
    const ivec2 q = p + kAxis * (2 * t);
    if (!aoeval_covered(q)) continue;
    const float dz = abs(imageLoad(aoeval_depth, q).r - z) / z;
    const float w = kGaussian[abs(t)] * max(0.0, 1.0 - aoeval.params.edge_sharpness * 100.0 * dz);
    sum += w * imageLoad(aoeval_prev, q).r;
    total += w;
  }
  imageStore(aoeval_out, p, vec4(sum / total));
}
