#include "harness/results/machine_class.h"

#include <algorithm>

namespace aoeval {

std::string machine_class(const ResultRow& row) {
  // run_context.cpp writes "hostname (CPU model, N cores)"; anything else is kept whole.
  std::string kind = row.machine;
  const size_t open = kind.find(" (");
  if (open != std::string::npos && !kind.empty() && kind.back() == ')')
    kind = kind.substr(open + 2, kind.size() - open - 3);
  return kind + " | " + row.device;
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
