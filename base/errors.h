// Error kinds shared by every layer. The command line maps them to exit codes (CONTRACT §2):
// InputError -> 2 (bad usage or bad input, one line saying what and where), anything else -> 1.
#pragma once

#include <stdexcept>
#include <string>

namespace aoeval {

// Bad input: a malformed scene, mesh, parameter or file. The message is one line that names the
// file and the field (or key) at fault.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A command that stops early on purpose (e.g. a sweep interrupted by SIGINT) with this exit status.
struct ExitStatus {
  int code;
};

}  // namespace aoeval
