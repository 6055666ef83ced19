// Limits on what aoeval accepts as input, in one place, each with the reason it exists. Inputs past
// them are InputErrors (exit 2) naming the file and field, instead of a crash, an allocation
// failure or a silently wrong image.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace aoeval {

// Scene coordinates (vertices after placement, eyes, targets, translations): Embree and the
// G-buffer work in 32-bit float. Beyond 1e7 the spacing of floats exceeds one scene unit, and far
// beyond it rays built from such points overflow to inf/NaN (Embree then asserts, or misses every
// triangle and the G-buffer comes out empty with exit 0). A real scene in metres or millimetres
// fits.
inline constexpr double kMaxSceneCoordinate = 1e7;

// JSON documents (scenes, sweep specs, suites, configs): aoeval's own formats nest fewer than ten
// levels; 64 leaves room and keeps every recursive walk over a parsed value (copies, dumps)
// shallow.
inline constexpr int kMaxJsonDepth = 64;
// No scene, spec or suite comes near this; a larger file is a mistake (or an attack on memory).
inline constexpr size_t kMaxJsonBytes = size_t{64} << 20;

// What one pixel costs through a whole evaluation: the G-buffer (14 floats), the reference (6), an
// estimate with its extra channels, error maps, OpenImageIO copies for writing and Vulkan images
// with their staging buffers. Measured peak resident memory of `aoeval estimate` and `reference`
// stays below this; it is a budget for refusing impossible resolutions up front, not an accounting.
inline constexpr size_t kBytesPerPixelBudget = 256;

// MemAvailable from /proc/meminfo in bytes, or 0 when it cannot be read (then nothing is refused).
size_t available_memory_bytes();
// InputError when width x height pixels at kBytesPerPixelBudget would not fit in available memory:
// "resolution 16384x16384 needs about 64.0 GiB of memory ... (this machine has 22.1 GiB
// available)".
void check_memory_for_resolution(int width, int height);

// Whether a double read from a file can become a float without overflowing (a cast of an
// out-of-range double to float is undefined behaviour, and in practice inf).
inline bool fits_float(double v) {
  return std::isfinite(v) && std::fabs(v) <= 3.4028234663852886e38;
}

}  // namespace aoeval
