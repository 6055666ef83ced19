// Image files. OpenEXR (32-bit float, one part) through OpenImageIO for G-buffers, references and
// estimates (CONTRACT §4); every write is atomic: a temporary file beside the target, then rename,
// so a failed or interrupted command never leaves a partial file.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <string>
#include <utility>
#include <vector>

#include "base/text_files.h"

namespace aoeval {

using Attributes = std::vector<std::pair<std::string, std::string>>;

// Writes `image` as a float OpenEXR with `compression` (zip unless a caller knows better, e.g. the
// report folder's float16-rounded files, kept_references.h) and `attributes` as string header
// attributes (names as given, e.g. "aoeval:scene").
void write_exr(const std::string& path, const OIIO::ImageBuf& image, const Attributes& attributes,
               const char* compression = "zip");
// Writes any format OIIO knows by the extension of `path` (PNG previews), atomically.
void write_image(const std::string& path, const OIIO::ImageBuf& image);

// Reads a whole image into memory as float; InputError naming the file when it cannot.
OIIO::ImageBuf read_image(const std::string& path);
// Index of a named channel; InputError naming the file and channel when absent.
int channel_index(const OIIO::ImageBuf& image, const std::string& name, const std::string& path);
// A header attribute as a string ("" when absent).
std::string string_attribute(const OIIO::ImageBuf& image, const std::string& name);

}  // namespace aoeval
