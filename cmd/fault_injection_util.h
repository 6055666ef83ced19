// What the kill tests share (fault_injection_test.cpp, sequence_kill_test.cpp): spawn the aoeval
// binary with its own reference cache and logs (so it can be SIGKILLed at any moment), and read
// what a killed and resumed sweep left: results.json's rows, SQLite's, results.csv's run names.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
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

inline size_t json_row_count(const fs::path& out) {
  try {
    const auto j = nlohmann::json::parse(slurp(out / "results.json"));
    return j["rows"].size();
  } catch (const std::exception&) {
    return 0;  // not written yet
  }
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

}  // namespace aoeval::cli_test
