// The SQLite helpers of SqliteStore's files (results_sqlite.cpp, results_sqlite_frames.cpp): a
// prepared statement finalized on scope exit, exec, and a BEGIN IMMEDIATE transaction rolled back
// unless committed. Internal to harness/results/.
#pragma once

#include <sqlite3.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "harness/results/results_store.h"

namespace aoeval::sqlite_detail {

inline std::string quote_identifier(const std::string& name) {
  std::string q = "\"";
  for (char c : name) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

[[noreturn]] inline void fail(sqlite3* db, const std::string& path, const std::string& what) {
  throw std::runtime_error("results database " + path + ": " + what + ": " +
                           (db ? sqlite3_errmsg(db) : "out of memory"));
}

// A prepared statement, finalized on scope exit.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& path, const std::string& sql) : db_(db), path_(path) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
      fail(db, path, "cannot prepare \"" + sql + "\"");
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* get() const { return stmt_; }
  void bind_text(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  }
  // Binds a flat value: null -> NULL (+Inf in metric columns: psnr of identical images), bool ->
  // 0/1, numbers as they are, arrays and objects as JSON text.
  void bind_json(int i, const nlohmann::json& v, const std::string& column) {
    if (v.is_null()) {
      if (is_metric_column(column)) {
        sqlite3_bind_double(stmt_, i, HUGE_VAL);
      } else {
        sqlite3_bind_null(stmt_, i);
      }
    } else if (v.is_boolean()) {
      sqlite3_bind_int(stmt_, i, v.get<bool>() ? 1 : 0);
    } else if (v.is_number_integer()) {
      sqlite3_bind_int64(stmt_, i, v.get<sqlite3_int64>());
    } else if (v.is_number()) {
      sqlite3_bind_double(stmt_, i, v.get<double>());
    } else {
      bind_text(i, v.is_string() ? v.get<std::string>() : v.dump());
    }
  }
  bool step() {  // true: a row is ready; false: done
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db_, path_, "statement failed");
  }
  std::string text(int i) const {
    const auto* t = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, i));
    return t ? std::string(t, static_cast<size_t>(sqlite3_column_bytes(stmt_, i))) : "";
  }

 private:
  sqlite3* db_;
  std::string path_;
  sqlite3_stmt* stmt_ = nullptr;
};

inline void exec(sqlite3* db, const std::string& path, const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string m = message ? message : "unknown error";
    sqlite3_free(message);
    throw std::runtime_error("results database " + path + ": " + sql + ": " + m);
  }
}

// BEGIN IMMEDIATE (takes the write lock up front, waiting up to the busy timeout), rolled back
// unless committed.
class Transaction {
 public:
  Transaction(sqlite3* db, const std::string& path) : db_(db), path_(path) {
    exec(db, path, "BEGIN IMMEDIATE");
  }
  ~Transaction() {
    if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit() {
    exec(db_, path_, "COMMIT");
    done_ = true;
  }

 private:
  sqlite3* db_;
  std::string path_;
  bool done_ = false;
};

}  // namespace aoeval::sqlite_detail
