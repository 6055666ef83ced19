// What the kill tests share (fault_injection_test.cpp, sequence_kill_test.cpp): spawn the aoeval
// binary with its own reference cache and logs (so it can be SIGKILLed at any moment), SIGKILL a
// sweep at random moments and resume it until it finishes, and read what it left: results.json's
// rows, SQLite's, results.csv's run names.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "base/testing/cli_test_util.h"

namespace aoeval::cli_test {

namespace fs = std::filesystem;

inline pid_t spawn_aoeval(const std::vector<std::string>& args, const fs::path& log_dir,
                          const std::string& cache) {
  std::vector<std::string> all = {AOEVAL_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_strings = {"AOEVAL_CACHE=" + cache};
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("AOEVAL_CACHE=", 0) != 0) env_strings.push_back(*e);
  std::vector<char*> envp;
  for (auto& e : env_strings) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, (log_dir / "out.log").c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, (log_dir / "err.log").c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  pid_t pid = 0;
  if (posix_spawn(&pid, AOEVAL_BINARY, &actions, nullptr, argv.data(), envp.data()) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// The rows a sweep has recorded in its folder so far: results.json's, and those appended to its
// journal (results.rows.jsonl) since results.json was last written whole; each run name once.
inline size_t json_row_count(const fs::path& out) {
  std::set<std::string> names;
  try {
    const auto j = nlohmann::json::parse(slurp(out / "results.json"));
    for (const auto& row : j["rows"]) names.insert(row["run_name"].get<std::string>());
  } catch (const std::exception&) {
    // not written yet
  }
  std::ifstream journal(out / "results.rows.jsonl");
  std::string line;
  while (std::getline(journal, line)) {
    const auto row = nlohmann::json::parse(line, nullptr, false);
    if (row.is_object() && row.contains("run_name") && row["run_name"].is_string())
      names.insert(row["run_name"].get<std::string>());  // a line cut short is not a row
  }
  return names.size();
}

inline std::vector<std::string> sqlite_strings(const fs::path& db, const std::string& sql) {
  sqlite3* h = nullptr;
  std::vector<std::string> out;
  if (sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(h, sql.c_str(), -1, &s, nullptr) == SQLITE_OK) {
      while (sqlite3_step(s) == SQLITE_ROW)
        out.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
    }
    sqlite3_finalize(s);
  }
  sqlite3_close(h);
  return out;
}

inline std::vector<std::string> csv_run_names(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  // run_id is the first column, run_name the second (identifying_columns()); names hold no comma.
  std::vector<std::string> names;
  while (std::getline(in, line)) {
    const size_t a = line.find(','), b = line.find(',', a + 1);
    names.push_back(line.substr(a + 1, b - a - 1));
  }
  return names;
}

// How a kill loop kills: each launch is SIGKILLed once 0 to max_wait_rows new rows (uniform) are
// recorded (json_row_count), after a further 0 to max_delay_us (uniform); a launch that writes no
// row within `polls` polls of 2 ms is killed then. The loop stops after max_kills SIGKILLs or
// max_launches launches, or when a launch finishes on its own.
struct KillSchedule {
  int max_kills = 0;
  int max_launches = 0;
  size_t max_wait_rows = 0;
  int max_delay_us = 0;
  int polls = 0;
};

struct KillCount {
  int kills = 0;     // launches that ended by the SIGKILL
  int launches = 0;  // every launch, the finishing one included
};

// `aoeval sweep SPEC --out OUT --db DB` (with --resume once results.json exists) launched and
// SIGKILLed again and again as `schedule` says (its randomness from `rng`), logs and the reference
// cache under `dir` and `cache`; when no launch finished on its own, one last --resume runs it to
// the end. Fails the test (fatally: wrap the call in ASSERT_NO_FATAL_FAILURE) when a launch or the
// last resume exits other than 0, and prints "<label>: N SIGKILLs over M launches".
inline void sweep_killed_and_resumed(const std::string& label, const std::string& spec,
                                     const fs::path& out, const fs::path& db, const fs::path& dir,
                                     const std::string& cache, std::mt19937& rng,
                                     const KillSchedule& schedule, KillCount* count) {
  size_t rows_before = 0;
  bool finished = false;
  while (count->kills < schedule.max_kills && count->launches < schedule.max_launches &&
         !finished) {
    std::vector<std::string> args = {"sweep", spec, "--out", out.string(), "--db", db.string()};
    if (fs::exists(out / "results.json")) args.push_back("--resume");
    const pid_t pid = spawn_aoeval(args, dir, cache);
    ASSERT_GT(pid, 0);
    ++count->launches;
    const size_t wait_rows = std::uniform_int_distribution<size_t>(0, schedule.max_wait_rows)(rng);
    const int delay_us = std::uniform_int_distribution<int>(0, schedule.max_delay_us)(rng);
    int status = 0;
    bool exited = false;
    for (int i = 0; i < schedule.polls; ++i) {
      if (waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      if (json_row_count(out) >= rows_before + wait_rows) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (!exited) {
      std::this_thread::sleep_for(std::chrono::microseconds(delay_us));
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      if (WIFSIGNALED(status)) ++count->kills;
    }
    if (WIFEXITED(status)) {
      ASSERT_EQ(WEXITSTATUS(status), 0) << slurp(dir / "err.log");
      finished = true;
    }
    rows_before = json_row_count(out);
  }
  if (!finished) {
    const Result r = run_aoeval(
        "AOEVAL_CACHE=" + cache + " ",
        "sweep " + spec + " --out " + out.string() + " --db " + db.string() + " --resume", dir);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  std::printf("%s: %d SIGKILLs over %d launches\n", label.c_str(), count->kills, count->launches);
}

}  // namespace aoeval::cli_test
