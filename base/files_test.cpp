// base/ (issue 28): the validating JSON reader refuses a key given twice, and atomic writes
// leave no temporary behind, whether their process was killed (the next run removes what a dead
// pid left) or interrupted (its own SIGINT handler removes them).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "base/json_reader.h"
#include "base/testing/test_temp_dir.h"
#include "base/text_files.h"

namespace {

namespace fs = std::filesystem;
using aoeval::InputError;

std::string error_of(const std::string& text) {
  try {
    aoeval::parse_json_text(text, "f.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(JsonReader, AKeyGivenTwiceIsAnErrorNamingItsPath) {
  EXPECT_EQ(error_of(R"({"a": 1, "a": 2})"),
            "f.json: a: duplicate key (a key may appear once in "
            "an object)");
  EXPECT_NE(error_of(R"({"runs": [{"x": 1}, {"grid": {"r": [1], "r": [2]}}]})")
                .find("f.json: runs[1].grid.r: duplicate key"),
            std::string::npos);
  EXPECT_NE(error_of(R"([[1, 2], {"k": 1, "k": 1}])").find("f.json: [1].k: duplicate key"),
            std::string::npos);
  // The same key in different objects, and in nested ones, is fine.
  EXPECT_EQ(error_of(R"({"a": {"a": 1}, "b": [{"a": 1}, {"a": 2}], "c": {"a": [{"a": 0}]}})"), "");
}

// Invalid JSON (NaN, Infinity: not JSON numbers) and a number no double holds name the key whose
// value was being read, in one line with no "[json.exception...]" text.
TEST(JsonReader, InvalidValuesNameTheirKey) {
  EXPECT_EQ(error_of("{\"defaults\": {\"max_rmse\": NaN}}"),
            "f.json:1:27: invalid JSON (at key defaults.max_rmse)");
  EXPECT_EQ(error_of("{\"a\": [1, 2, Infinity]}"), "f.json:1:14: invalid JSON (at key a[2])");
  EXPECT_EQ(error_of("{\"defaults\": {\"max_rmse\": 1e400}}"),
            "f.json: invalid JSON at key defaults.max_rmse: number overflow parsing '1e400'");
}

// An atomic write aimed at a folder is bad input naming the path (it was a failed rename naming
// this process's temporary), and leaves nothing behind.
TEST(Temporaries, WritingOverAFolderIsAnInputErrorNamingIt) {
  const fs::path d = aoeval::testutil::test_temp_dir("files") / "a-folder";
  fs::create_directories(d);
  for (const std::string& path : {d.string(), d.string() + "/"}) {
    try {
      aoeval::write_text(path, "{}");
      ADD_FAILURE() << path << " written";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), path + ": is a folder; give the path of a file to write");
    }
  }
  EXPECT_TRUE(fs::is_empty(d));
}

// A pid that ran and is gone: a child that exited and was reaped.
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

TEST(Temporaries, ADeadProcessesTemporariesAreRemovedALiveOnesKept) {
  const fs::path d = aoeval::testutil::test_temp_dir("files");
  const fs::path target = d / "ref.exr";
  const fs::path dead = d / (".ref.tmp-" + std::to_string(dead_pid()) + "-0.exr");
  const fs::path live = d / (".ref.tmp-" + std::to_string(getppid()) + "-3.exr");
  const fs::path other = d / (".other.tmp-" + std::to_string(dead_pid()) + "-0.exr");
  for (const auto& p : {dead, live, other}) std::ofstream(p) << "partial";
  EXPECT_EQ(aoeval::remove_dead_temporaries_of(target.string()), 1u);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));   // its process runs: perhaps writing now
  EXPECT_TRUE(fs::exists(other));  // another target's
  // Under a lock every writer of the target takes, every temporary of it is a dead one's.
  EXPECT_EQ(aoeval::remove_temporaries_of(target.string()), 1u);
  EXPECT_FALSE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
}

TEST(Temporaries, SigintRemovesTheOpenTemporariesAndExits130) {
  const fs::path d = aoeval::testutil::test_temp_dir("files");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  if (child == 0) {
    aoeval::install_interrupt_cleanup();
    const std::string tmp = aoeval::temporary_path_for((d / "out.exr").string());
    std::ofstream(tmp) << "half an image";
    if (write(ready[1], "x", 1) != 1) _exit(3);
    pause();  // interrupted here, as if in the middle of writing
    _exit(4);
  }
  char c;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  size_t before = 0;
  for (const auto& e : fs::directory_iterator(d)) before += e.path().filename().string()[0] == '.';
  EXPECT_EQ(before, 1u);
  kill(child, SIGINT);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_TRUE(fs::is_empty(d)) << (*fs::directory_iterator(d)).path();
}

}  // namespace
