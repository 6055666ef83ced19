// What the tests of commands that draw check of a PNG they wrote: a whole PNG file (signature,
// IHDR, chunks that fit the file, IEND last) and its size, read from the file's own header. A file
// of the right length but of other bytes, a truncated one or an empty drawing fails; a size test
// (file_size > 1000) passed for all of them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace aoeval::testutil {

struct PngInfo {
  std::string problem;  // "" for a whole PNG
  uint32_t width = 0, height = 0;
  uint64_t image_data_bytes = 0;  // the IDAT chunks' total (compressed) length
};

inline PngInfo read_png_info(const std::filesystem::path& path) {
  PngInfo info;
  std::ifstream in(path, std::ios::binary);
  const std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto u32 = [&](size_t at) {
    return (uint32_t(uint8_t(b[at])) << 24) | (uint32_t(uint8_t(b[at + 1])) << 16) |
           (uint32_t(uint8_t(b[at + 2])) << 8) | uint32_t(uint8_t(b[at + 3]));
  };
  if (b.size() < 8 || b.compare(0, 8, "\x89PNG\r\n\x1a\n", 8) != 0) {
    info.problem = path.string() + ": not a PNG (no signature)";
    return info;
  }
  size_t at = 8;
  bool first = true, ended = false;
  while (at + 12 <= b.size() && !ended) {
    const uint32_t length = u32(at);
    const std::string type = b.substr(at + 4, 4);
    if (at + 12 + uint64_t(length) > b.size()) break;
    if (first && (type != "IHDR" || length != 13)) {
      info.problem = path.string() + ": the first chunk is not IHDR";
      return info;
    }
    if (first) {
      info.width = u32(at + 8);
      info.height = u32(at + 12);
    }
    if (type == "IDAT") info.image_data_bytes += length;
    ended = type == "IEND";
    first = false;
    at += 12 + length;
  }
  if (!ended)
    info.problem = path.string() + ": truncated (no IEND chunk where the chunks end)";
  else if (at != b.size())
    info.problem = path.string() + ": bytes after IEND";
  else if (info.width == 0 || info.height == 0 || info.image_data_bytes == 0)
    info.problem = path.string() + ": no image";
  return info;
}

}  // namespace aoeval::testutil
