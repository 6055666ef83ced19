// The one reader of AO EXRs (references, estimates, any file `aoeval compare` is given): the AO and
// A (coverage) channels, and the optional AO_stderr, bent.X/Y/Z, bent_stderr and spp channels and
// the aoeval:scene/view/definition attributes. Every reader of such a file goes through it, so a
// file means the same thing to compare, the dashboard and the reference cache.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "base/coverage.h"

namespace aoeval {

// AO is accessibility in [0, 1] (CONTRACT §3). Values within this of the range are float rounding
// in someone's arithmetic (1 - sum giving 1.0000001); anything further out means the file or the
// program holds something other than accessibility.
inline constexpr float kAoRangeSlack = 1e-3f;
// AO_stderr, the standard error of a mean of values in [0, 1], is at most 0.5 (the largest
// standard deviation such values can have; sampling/ao_tracer.cpp's bound with one sample).
inline constexpr float kMaxAoStderr = 0.5f;

struct AoExr {
  std::string path;  // the file it was read from
  int width = 0, height = 0;
  std::vector<float> ao, coverage;  // per pixel, row-major
  bool covered(size_t k) const { return is_covered(coverage[k]); }
  std::vector<float> stderr_ao;         // empty when the file has no AO_stderr channel
  std::vector<glm::vec3> bent;          // empty unless bent.X, bent.Y and bent.Z are all present
  std::vector<float> spp;               // empty without an spp channel
  std::vector<float> bent_stderr;       // a reference's bent-normal noise (degrees); may be empty
  std::string scene, view, definition;  // aoeval: attributes, "" where absent
};

// InputError naming the file when it is missing, unreadable, or lacks AO or A (or AO_stderr when
// `need_stderr`), and naming the pixel and its value when a covered pixel's AO is NaN, infinite,
// or outside [0, 1] by more than kAoRangeSlack, or when a covered pixel's AO_stderr is NaN,
// infinite, negative or above kMaxAoStderr (by more than the slack): scoring such a file would turn
// it into plausible numbers (a NaN or huge stderr made rmse_excess 0, a perfect score).
AoExr read_ao_exr(const std::string& path, bool need_stderr = false);
// The same from an image already read from `path` (the reference cache reads a file once to
// verify it and to use it).
AoExr ao_exr_from_image(const OIIO::ImageBuf& image, const std::string& path,
                        bool need_stderr = false);

}  // namespace aoeval
