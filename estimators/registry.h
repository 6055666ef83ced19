// The estimator registry. Registration is explicit: registry.cpp calls each estimator folder's
// declaration function by name, so no estimator can be dropped by the linker or registered twice
// by accident. Adding an estimator = one add_subdirectory line and one line in registry.cpp.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "estimators/estimator.h"

namespace aoeval {

// Built-ins, then plug-ins (CONTRACT §7): the shipped examples and $AOEVAL_PLUGINS are read on the
// first call, --plugins folders by add_plugin_dir(). A plug-in folder that cannot be read (a bad
// manifest, a name clash) is skipped with a warning on stderr naming it, said by the next
// estimator_registry() or find_estimator(); find_estimator() of its name is then an InputError
// quoting why (exit 2 before any work), not also said as a warning before it. A deque, so the
// references and pointers to its entries that commands and runners keep stay valid while plug-ins
// are added.
const std::deque<EstimatorInfo>& estimator_registry();
// Adds the plug-ins of `dir` (a plug-in folder or a folder of them; see plugin_registry.h). Call
// it before taking references into the registry (commands do, while parsing --plugins).
void add_plugin_dir(const std::string& dir);
// InputError listing the known estimators when `name` is unknown, or quoting the error of the
// broken plug-in that declares `name`.
const EstimatorInfo& find_estimator(const std::string& name);
// The code that makes an estimator's output, as the results' estimator_version column records it:
// "<kind>:<12 hex digits>". A built-in's hashes its folder and our libraries it links (computed
// at build time, estimators/CMakeLists.txt); a plug-in's its manifest and the shader or program
// files it names, when it was read (plugin_code_version). "" for an estimator not registered.
std::string estimator_code_version(const EstimatorInfo& e);
// The device an estimator of backend `b` runs on, for the results' `device` column: the Vulkan
// device's description for vulkan (e.g. "llvmpipe (LLVM 15.0.6, 256 bits) [cpu, Mesa 22.3.6]"),
// "" for the CPU backends (the caller uses the machine's CPU) and when there is no Vulkan device.
std::string backend_device(Backend b);

}  // namespace aoeval
