#include "base/input_limits.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "base/errors.h"

namespace aoeval {

size_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  size_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit) {
    if (key == "MemAvailable:") return kib * 1024;
  }
  return 0;
}

void check_memory_for_resolution(int width, int height) {
  const double needed = static_cast<double>(width) * static_cast<double>(height) *
                        static_cast<double>(kBytesPerPixelBudget);
  const size_t available = available_memory_bytes();
  if (available == 0 || needed <= static_cast<double>(available)) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char message[256];
  std::snprintf(message, sizeof message,
                "res: %dx%d needs about %.1f GiB of memory (%zu bytes per pixel for the G-buffer, "
                "reference, estimates and maps); this machine has %.1f GiB available",
                width, height, needed / kGiB, kBytesPerPixelBudget,
                static_cast<double>(available) / kGiB);
  throw InputError(message);
}

}  // namespace aoeval
