#include "harness/results/machine_class.h"

#include <algorithm>

namespace aoeval {

std::string machine_class(const ResultRow& row) {
  // run_context.cpp writes "hostname (CPU model, N cores)"; anything else is kept whole.
  std::string kind = row.machine;
  const size_t open = kind.find(" (");
  if (open != std::string::npos && !kind.empty() && kind.back() == ')')
    kind = kind.substr(open + 2, kind.size() - open - 3);
  // A CPU row's device is the machine's CPU (the kind starts with it), and so is a software Vulkan
  // device's (lavapipe, whose driver is llvmpipe): one device, "CPU", that the leaderboard compares
  // on one machine. Any other device (a real GPU) makes a class of its own.
  const bool on_the_cpu = row.device.find("llvmpipe") != std::string::npos ||
                          (!row.device.empty() && kind.rfind(row.device, 0) == 0);
  return kind + " | " + (on_the_cpu ? std::string("CPU") : row.device);
}

std::vector<std::string> machine_classes(const std::vector<ResultRow>& rows) {
  std::vector<std::string> out;
  for (const ResultRow& r : rows) {
    const std::string c = machine_class(r);
    if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  }
  return out;
}

}  // namespace aoeval
