// What the fuzz targets share: the readers under test take a path (they resolve mesh paths
// relative to the scene file), so each input is written to one private temporary file first.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace aoeval::fuzz {

inline std::string write_input(const uint8_t* data, size_t size, const char* extension) {
  static const std::string path =
      "/tmp/aoeval-fuzz-" + std::to_string(getpid()) + "/input" + extension;
  static const bool made = [] {
    const std::string dir = "/tmp/aoeval-fuzz-" + std::to_string(getpid());
    return std::system(("mkdir -p " + dir).c_str()) == 0;
  }();
  (void)made;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace aoeval::fuzz
