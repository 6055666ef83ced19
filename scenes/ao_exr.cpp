#include "scenes/ao_exr.h"

#include <cstdio>

#include "base/errors.h"
#include "scenes/exr_io.h"

namespace aoeval {

AoExr read_ao_exr(const std::string& path, bool need_stderr) {
  return ao_exr_from_image(read_image(path), path, need_stderr);
}

AoExr ao_exr_from_image(const OIIO::ImageBuf& image, const std::string& path, bool need_stderr) {
  const OIIO::ImageSpec& spec = image.spec();
  AoExr f;
  f.path = path;
  f.width = spec.width;
  f.height = spec.height;
  const int ao = channel_index(image, "AO", path);
  const int se =
      need_stderr ? channel_index(image, "AO_stderr", path) : spec.channelindex("AO_stderr");
  const int a = channel_index(image, "A", path);
  const int bx = spec.channelindex("bent.X"), by = spec.channelindex("bent.Y"),
            bz = spec.channelindex("bent.Z"), sp = spec.channelindex("spp"),
            bs = spec.channelindex("bent_stderr");
  const size_t n = static_cast<size_t>(f.width) * f.height, nc = spec.nchannels;
  std::vector<float> all(n * nc);
  if (!image.get_pixels(OIIO::ROI::All(), OIIO::TypeFloat, all.data()))
    throw InputError(path + ": cannot read its pixels: " + image.geterror());
  f.ao.resize(n);
  f.coverage.resize(n);
  if (se >= 0) f.stderr_ao.resize(n);
  const bool bent = bx >= 0 && by >= 0 && bz >= 0;
  if (bent) f.bent.resize(n);
  if (sp >= 0) f.spp.resize(n);
  if (bs >= 0) f.bent_stderr.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const float* s = all.data() + k * nc;
    f.ao[k] = s[ao];
    f.coverage[k] = s[a];
    if (se >= 0) f.stderr_ao[k] = s[se];
    if (bent) f.bent[k] = {s[bx], s[by], s[bz]};
    if (sp >= 0) f.spp[k] = s[sp];
    if (bs >= 0) f.bent_stderr[k] = s[bs];
    if (se >= 0 && f.covered(k) &&
        !(f.stderr_ao[k] >= 0.0f && f.stderr_ao[k] <= kMaxAoStderr + kAoRangeSlack)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", static_cast<double>(f.stderr_ao[k]));
      throw InputError(path + ": AO_stderr value " + value + " at pixel (" +
                       std::to_string(k % f.width) + ", " + std::to_string(k / f.width) +
                       ") is outside [0, 0.5] (the standard error of a mean of values in [0, 1] "
                       "is finite and at most 0.5)");
    }
    if (f.covered(k) && !(f.ao[k] >= -kAoRangeSlack && f.ao[k] <= 1.0f + kAoRangeSlack)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", static_cast<double>(f.ao[k]));
      throw InputError(path + ": AO value " + value + " at pixel (" + std::to_string(k % f.width) +
                       ", " + std::to_string(k / f.width) +
                       ") is outside [0, 1] (AO is accessibility: 0 = fully occluded, 1 = open)");
    }
  }
  f.scene = string_attribute(image, "aoeval:scene");
  f.view = string_attribute(image, "aoeval:view");
  f.definition = string_attribute(image, "aoeval:definition");
  return f;
}

}  // namespace aoeval
