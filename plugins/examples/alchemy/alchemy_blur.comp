#version 450
// The depth-aware blur after the Alchemy estimator (second pass; reads aoeval_prev, writes
// aoeval_out). The estimator's s disk samples are rotated per pixel by the noise tile, so the raw
// estimate carries the tile's per-pixel noise; this pass removes it, as the reconstruction filter
// of the same authors' successor, Scalable Ambient Obscurance (McGuire, Mara, Luebke 2012), does.
// One 2D pass over the (2 r + 1)^2 pixels around p: a Gaussian of standard deviation r / 2 pixels,
// each weight multiplied by max(0, 1 - edge_sharpness * 100 |z_q - z_p| / z_p) so that it does not
// blur across depth edges (as the sao example's filter; depth is relative to the pixel's own,
// aoeval's projection having no far plane), and only over covered pixels. r = blur_radius; 0 copies
// the raw estimate. One pass rather than two separable ones keeps the example to one file per
// job, at (2 r + 1)^2 reads: 49 at the default r = 3.
layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (!aoeval_inside(p)) return;
  const float raw = imageLoad(aoeval_prev, p).r;
  const int r = aoeval.params.blur_radius;
  if (r == 0 || !aoeval_covered(p)) {
    imageStore(aoeval_out, p, vec4(raw));
    return;
  }
  const float z = imageLoad(aoeval_depth, p).r;
  const float inv_two_sigma2 = 2.0 / float(r * r);  // sigma = r / 2: 1 / (2 sigma^2) = 2 / r^2
  float sum = 0.0, total = 0.0;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const ivec2 q = p + ivec2(dx, dy);
      if (!aoeval_covered(q)) continue;  // off screen or background
      const float dz = abs(imageLoad(aoeval_depth, q).r - z) / z;
      const float w = exp(-float(dx * dx + dy * dy) * inv_two_sigma2) *
                      max(0.0, 1.0 - aoeval.params.edge_sharpness * 100.0 * dz);
      sum += w * imageLoad(aoeval_prev, q).r;
      total += w;
    }
  }
  // The centre's own weight is 1 (dx = dy = 0, dz = 0), so total >= 1.
  imageStore(aoeval_out, p, vec4(sum / total));
}
