// The tests' temporary folders, in one place. ctest runs every test in a process of its own and
// several build folders (a developer's, a fresh clone's, CI's) may run the same test at once, so a
// folder is named by label, test and process id: <tmp>/aoeval_<label>_<test>_<pid>. It is created
// empty on first use, and removed when the process ends with every test passed (kept for a look
// when one failed).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <system_error>

namespace aoeval::testutil {

namespace detail {
struct TempDirRegistry {
  std::set<std::filesystem::path> dirs;
  ~TempDirRegistry() {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ignored;
    for (const auto& d : dirs) std::filesystem::remove_all(d, ignored);
  }
};
inline TempDirRegistry& temp_dir_registry() {
  static TempDirRegistry registry;  // built after gtest's UnitTest, so destroyed before it
  return registry;
}
}  // namespace detail

// This test's folder for `label`: the same path on every call within a test.
inline std::filesystem::path test_temp_dir(const std::string& label) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "aoeval_" + label;
  if (test) name.append("_").append(test->test_suite_name()).append("_").append(test->name());
  name.append("_").append(std::to_string(getpid()));
  for (char& c : name)
    if (c == '/') c = '_';  // parameterised tests are named "Suite/Test/0"
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
  if (detail::temp_dir_registry().dirs.insert(dir).second) {
    std::filesystem::remove_all(dir);  // left by an earlier process with the same id
    std::filesystem::create_directories(dir);
  }
  return dir;
}

}  // namespace aoeval::testutil
