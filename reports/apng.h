// Animated PNG (APNG; Mozilla's specification, https://wiki.mozilla.org/APNG_Specification, which
// PNG 3rd edition adopted): the sequence videos of the report. Lossless, so a grey panel plays
// exactly its 8-bit greys (a GIF's 256-colour palette, as OpenImageIO's GIF writer builds it,
// held only 27 colours of a sequence frame and moved greys by up to 23 levels), and browsers play
// it in an <img> with no script, from file://. The frames' pixels are compressed by OpenImageIO's
// PNG writer; this file only re-chunks them (acTL, fcTL, fdAT).
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <string>
#include <vector>

namespace aoeval {

// Writes `frames` (equal sizes, 8-bit, 1-4 channels) as an endlessly looping APNG at `fps`
// frames per second (10 when fps <= 0) to `path`, atomically. std::runtime_error when the frames
// differ in size or OpenImageIO cannot write a PNG. Frames that are all grey (3 channels, R = G = B
// in every pixel of every frame) are written as one grey channel, losslessly.
void write_apng(const std::vector<OIIO::ImageBuf>& frames, double fps, const std::string& path);

}  // namespace aoeval
