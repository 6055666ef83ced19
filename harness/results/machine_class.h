// Timing across nodes (issue 19): rows merged from several machines carry each its own `machine`
// ("hostname (CPU model, N cores)") and `device`. Times are comparable only between rows measured
// on the same kind of machine and device, not between, say, a 64-core node and a laptop; the
// hostname itself does not matter (two nodes of one partition are one class).
#pragma once

#include <string>
#include <vector>

#include "harness/results/result_row.h"

namespace aoeval {

// "CPU model, N cores | device": the machine string without its host name, and the device, "CPU"
// for the machine's CPU and for lavapipe (software Vulkan on that CPU): a CPU row and a lavapipe
// row of one machine are one class, their times compare, as the leaderboard puts them together.
std::string machine_class(const ResultRow& row);
// The distinct classes of `rows`, in order of first appearance.
std::vector<std::string> machine_classes(const std::vector<ResultRow>& rows);

}  // namespace aoeval
