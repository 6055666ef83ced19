// Coverage (CONTRACT §3, §4): a pixel is covered where its A channel is 1 (a surface), and only
// pixels covered in both images are compared. A is stored as a float; the one test of it is here,
// so a G-buffer, an AO image and every mask built from them agree on which pixels count.
#pragma once

namespace aoeval {

// A = 1 against A = 0, with any rounding of the stored value (resampling, a lossy tool) between.
inline constexpr bool is_covered(float a) {
  return a > 0.5f;
}

}  // namespace aoeval
