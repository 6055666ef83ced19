// What the command-line tests share: run the aoeval binary (AOEVAL_BINARY, a compile definition
// of each test target) through the shell and capture its exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace aoeval::cli_test {

struct Result {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `<prefix>AOEVAL_BINARY <args>` with no stdin; stdout and stderr go to files in
// `capture_dir` (read back into the result). `prefix` sets environment variables or a folder
// ("cd DIR && ", "AOEVAL_CACHE=... ").
inline Result run_aoeval(const std::string& prefix, const std::string& args,
                         const std::filesystem::path& capture_dir) {
  const std::string cmd = prefix + std::string(AOEVAL_BINARY) + " " + args + " >" +
                          (capture_dir / "stdout").string() + " 2>" +
                          (capture_dir / "stderr").string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(capture_dir / "stdout"),
          slurp(capture_dir / "stderr")};
}

}  // namespace aoeval::cli_test
