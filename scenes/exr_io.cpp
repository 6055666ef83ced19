#include "scenes/exr_io.h"

#include <OpenImageIO/imageio.h>
#include <zlib.h>

#include <atomic>
#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "scenes/pxr24_level.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {
void write_with(const std::string& path, const OIIO::ImageBuf& image, const char* format,
                OIIO::TypeDesc type) {
  const std::string tmp = temporary_path_for(path);
  if (!image.write(tmp, type, format)) {
    discard_temporary(tmp);
    throw std::runtime_error("cannot write " + path + ": " + image.geterror());
  }
  commit_temporary(tmp, path);
}
}  // namespace

void write_exr(const std::string& path, const OIIO::ImageBuf& image, const Attributes& attributes,
               const char* compression) {
  OIIO::ImageBuf out = image;  // cheap relative to the write; keeps the caller's spec untouched
  OIIO::ImageSpec& spec = out.specmod();
  spec.attribute("compression", compression);
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  write_with(path, out, "openexr", OIIO::TypeDesc::FLOAT);
}

void write_image(const std::string& path, const OIIO::ImageBuf& image) {
  if (fs::path(path).extension() == ".png") {
    // zlib level 1 instead of 6: a third less time per mosaic, and no larger on these images
    // (measured on the quick suite's mosaics: 20 ms / 293 KB against 32 ms / 294 KB). And no row
    // filter (PNG_FILTER_NONE): on these noisy grey and colour-mapped panels libpng's adaptive
    // filters hurt deflate; 21 of the default report's mosaics, strips and map figures took
    // 6.57 MB and 0.97 s with them, 4.85 MB and 0.49 s without (issue 42).
    OIIO::ImageBuf out = image;
    out.specmod().attribute("png:compressionLevel", 1);
    out.specmod().attribute("png:filter", 0x08);  // PNG_FILTER_NONE
    write_with(path, out, "", OIIO::TypeDesc::UNKNOWN);
    return;
  }
  write_with(path, image, "", OIIO::TypeDesc::UNKNOWN);
}

OIIO::ImageBuf read_image(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path + ": file not found");
  OIIO::ImageBuf image(path);
  if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    throw InputError(path + ": cannot read image: " + image.geterror());
  }
  return image;
}

int channel_index(const OIIO::ImageBuf& image, const std::string& name, const std::string& path) {
  int c = image.spec().channelindex(name);
  if (c < 0) throw InputError(path + ": channel '" + name + "' is missing");
  return c;
}

std::string string_attribute(const OIIO::ImageBuf& image, const std::string& name) {
  return image.spec().get_string_attribute(name);
}

namespace {
std::atomic<uint64_t> pxr24_deflates{0};
}  // namespace

uint64_t pxr24_deflate_count() {
  return pxr24_deflates.load(std::memory_order_relaxed);
}

}  // namespace aoeval

// zlib's compress() for OpenEXR's PXR24 writes (scenes/pxr24_level.h): compress2() at
// kPxr24ZlibLevel, same contract (*dest_len holds the buffer's size on entry, the stream's on
// return). Here, beside write_exr, so that every binary writing EXRs links it.
extern "C" int compress(Bytef* dest, uLongf* dest_len, const Bytef* source, uLong source_len) {
  aoeval::pxr24_deflates.fetch_add(1, std::memory_order_relaxed);
  return compress2(dest, dest_len, source, source_len, aoeval::kPxr24ZlibLevel);
}
