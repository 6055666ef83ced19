// The SQLite results history of SqliteStore (results_store.h): WAL journal, busy timeout so
// concurrent shards can append, one transaction per row, versioned schema, a parameter or pass
// column added by ALTER TABLE the first time a row brings it. Values are always bound, never
// spliced into SQL; identifiers are quoted.
#include <sqlite3.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "base/summary.h"
#include "harness/results/results_store.h"
#include "harness/results/sqlite_statement.h"

namespace aoeval {

namespace fs = std::filesystem;

using namespace sqlite_detail;

namespace {

std::string column_type(const std::string& column) {
  static const std::set<std::string> integers = {"width", "height", "repetitions", "pixels",
                                                 "true_pixels"};
  if (integers.count(column)) return " INTEGER";
  if (is_metric_column(column) || column.rfind("time_ms", 0) == 0 || column == "precompute_ms") {
    return " REAL";
  }
  return " TEXT";
}

constexpr int kBusyTimeoutMs = 60000;

// Why the open database is not an aoeval results database, or "" when it is one. With `new_ok`, a
// database without a schema version and without tables (a new file) is accepted too. The one check
// for the dashboard's read-only opening and the writers' (another application's file is refused by
// both, and never converted).
std::string not_an_aoeval_database(sqlite3* db, const std::string& path, bool new_ok) {
  Statement version(db, path, "PRAGMA user_version");
  const int v = version.step() ? sqlite3_column_int(version.get(), 0) : 0;
  if (v == 0 && new_ok) {
    Statement tables(db, path,
                     "SELECT group_concat(name, ', ') FROM sqlite_master WHERE type = 'table'");
    const std::string names = tables.step() ? tables.text(0) : "";
    return names.empty() ? ""
                         : "not an aoeval results database (it holds other tables: " + names + ")";
  }
  if (new_ok && v > kResultsSchemaVersion) return "";  // the writer names it: a newer aoeval's
  if (v != kResultsSchemaVersion) {
    return "not an aoeval results database (schema version " + std::to_string(v) + ", expected " +
           std::to_string(kResultsSchemaVersion) + ")";
  }
  Statement tables(db, path,
                   "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name IN "
                   "('runs', 'results', 'meta')");
  if (!tables.step() || sqlite3_column_int(tables.get(), 0) != 3)
    return "not an aoeval results database (tables runs, results and meta missing)";
  return "";
}

}  // namespace

void SqliteStore::open_read_only() {
  auto reject = [this](const std::string& why) {
    sqlite3_close_v2(db_);  // deferred until the statements alive in this scope are finalized
    db_ = nullptr;
    throw InputError("--db " + path_ + ": " + why);
  };
  if (!fs::is_regular_file(path_)) reject("no such file");
  // SQLite opens a WAL-mode file read-only by creating its -wal and -shm files beside it when they
  // are absent: that would add files beside someone's database. With no -wal file there is
  // nothing uncommitted to read, so the file is opened as immutable (no side files, no locks);
  // with one (a writer is live, or died), SQLite reads it as usual so no committed row is missed.
  std::error_code ec;
  const bool has_wal = fs::exists(path_ + "-wal", ec);
  std::string uri = "file:";
  for (char c : path_) {
    if (c == '%' || c == '?' || c == '#') {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", static_cast<unsigned char>(c));
      uri += hex;
    } else {
      uri += c;
    }
  }
  if (!has_wal) uri += "?immutable=1";
  if (sqlite3_open_v2(uri.c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) !=
      SQLITE_OK)
    reject(std::string("cannot open: ") + (db_ ? sqlite3_errmsg(db_) : "out of memory"));
  sqlite3_busy_timeout(db_, kBusyTimeoutMs);
  try {
    // The first read of the schema is where a corrupt or non-SQLite file fails ("file is not a
    // database"); a foreign database has other tables or another user_version.
    if (const std::string why = not_an_aoeval_database(db_, path_, false); !why.empty())
      reject(why);
    // Reads the whole file's b-tree structure once, so a corrupt page is found here, not halfway
    // through building a page of results.
    Statement check(db_, path_, "PRAGMA quick_check");
    const std::string verdict = check.step() ? check.text(0) : "no answer";
    if (verdict != "ok") reject("corrupt database (" + verdict + ")");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    std::string what = e.what();
    if (auto p = what.rfind(": "); p != std::string::npos) what = what.substr(p + 2);
    reject("not a readable aoeval results database (" + what + ")");
  }
}

SqliteStore::SqliteStore(const std::string& path, Mode mode) : path_(path) {
  if (mode == Mode::read_only) {
    open_read_only();
    return;
  }
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
  std::error_code ec;
  const bool existed = fs::exists(path, ec);
  if (existed && !fs::is_regular_file(path, ec)) throw InputError("--db " + path + ": not a file");
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw std::runtime_error("cannot open results database " + path + ": " + message);
  }
  try {
    sqlite3_busy_timeout(db_, kBusyTimeoutMs);
    // Before the first write (journal_mode writes the header): another application's database,
    // or a file that is no database at all, is the user's mistake and stays byte-identical.
    std::string why;
    try {
      why = not_an_aoeval_database(db_, path_, /*new_ok=*/true);
    } catch (const std::runtime_error&) {
      const int code = sqlite3_errcode(db_);
      if (code != SQLITE_NOTADB && code != SQLITE_CORRUPT) throw;
      why = std::string("not a readable SQLite database (") + sqlite3_errmsg(db_) + ")";
    }
    if (!why.empty()) throw InputError("--db " + path + ": " + why);
    exec(db_, path_, "PRAGMA journal_mode = WAL");
    Transaction t(db_, path_);
    Statement version(db_, path_, "PRAGMA user_version");
    const int v = version.step() ? sqlite3_column_int(version.get(), 0) : 0;
    if (v > kResultsSchemaVersion) {
      throw std::runtime_error("results database " + path + " has schema version " +
                               std::to_string(v) + ", newer than this aoeval's (" +
                               std::to_string(kResultsSchemaVersion) + ")");
    }
    if (v < kResultsSchemaVersion) {  // version 0 = new file; no older version exists yet
      exec(db_, path_, "CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT)");
      exec(db_, path_,
           "CREATE TABLE IF NOT EXISTS runs (run_id TEXT PRIMARY KEY, command TEXT, machine TEXT, "
           "device TEXT, git_commit TEXT, started TEXT, context TEXT)");
      std::string create =
          "CREATE TABLE IF NOT EXISTS results (id INTEGER PRIMARY KEY AUTOINCREMENT";
      for (const auto& c : identifying_columns())
        create += ", " + quote_identifier(c) + column_type(c);
      for (const auto& c : measured_columns())
        create += ", " + quote_identifier(c) + column_type(c);
      exec(db_, path_, create + ")");
      exec(db_, path_, "CREATE INDEX IF NOT EXISTS results_run_id ON results (run_id)");
      Statement meta(db_, path_, "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)");
      meta.bind_text(1, "schema_version");
      meta.bind_text(2, std::to_string(kResultsSchemaVersion));
      meta.step();
      Statement created(db_, path_, "INSERT OR IGNORE INTO meta (key, value) VALUES (?, ?)");
      created.bind_text(1, "created");
      created.bind_text(2, utc_now());
      created.step();
      exec(db_, path_, "PRAGMA user_version = " + std::to_string(kResultsSchemaVersion));
    }
    // add() replaces a row by (run_id, run_name): without this index each row's DELETE scanned
    // every earlier row of its run, quadratic in a sweep's points. Added to older files too (an
    // index changes no row).
    exec(db_, path_, "CREATE INDEX IF NOT EXISTS results_run_name ON results (run_id, run_name)");
    create_point_tables();
    t.commit();
  } catch (...) {
    sqlite3_close(db_);
    if (!existed) {  // a file this call created is not left behind
      fs::remove(path, ec);
      for (const char* side : {"-wal", "-shm", "-journal"}) fs::remove(path + side, ec);
    }
    throw;
  }
}

SqliteStore::~SqliteStore() {
  sqlite3_close(db_);
}

void SqliteStore::add_run(const RunContext& context) {
  Statement s(db_, path_,
              "INSERT OR REPLACE INTO runs (run_id, command, machine, device, git_commit, started, "
              "context) VALUES (?, ?, ?, ?, ?, ?, ?)");
  const std::string values[] = {context.run_id,         context.command,    context.machine,
                                context.device,         context.git_commit, context.started,
                                to_json(context).dump()};
  for (int i = 0; i < 7; ++i) s.bind_text(i + 1, values[i]);
  s.step();
}

std::vector<std::string> SqliteStore::columns() {
  Statement s(db_, path_, "PRAGMA table_info(results)");
  std::vector<std::string> out;
  while (s.step()) out.push_back(s.text(1));
  return out;
}

void SqliteStore::add(const ResultRow& row) {
  Transaction t(db_, path_);
  insert_row(row);
  t.commit();
}

void SqliteStore::add(const PointRecord& record) {
  Transaction t(db_, path_);
  insert_row(record.row);
  replace_frames(record.row, record.frames);
  replace_images(record.row, record.images);
  t.commit();
}

void SqliteStore::insert_row(const ResultRow& row) {
  const nlohmann::json flat = flatten(row);
  const std::vector<std::string> wanted = result_columns({row});
  // Inside the transaction: another process may have added columns since our last look.
  const std::vector<std::string> have = columns();
  const std::set<std::string> present(have.begin(), have.end());
  std::vector<std::string> names;
  for (const auto& c : wanted) {
    if (!flat.contains(c)) continue;
    if (!present.count(c)) {
      // Parameter columns take values as bound (no affinity); pass times are REAL.
      exec(db_, path_,
           "ALTER TABLE results ADD COLUMN " + quote_identifier(c) +
               (row.pass_ms.count(c) ? " REAL" : ""));
    }
    names.push_back(c);
  }
  // Idempotent per (run_id, run_name): a resumed sweep that stores a row again replaces it.
  Statement drop(db_, path_, "DELETE FROM results WHERE run_id = ? AND run_name = ?");
  drop.bind_text(1, row.run_id);
  drop.bind_text(2, row.run_name);
  drop.step();
  std::string sql = "INSERT INTO results (", marks;
  for (size_t i = 0; i < names.size(); ++i) {
    sql += (i ? ", " : "") + quote_identifier(names[i]);
    marks += i ? ", ?" : "?";
  }
  Statement insert(db_, path_, sql + ") VALUES (" + marks + ")");
  for (size_t i = 0; i < names.size(); ++i) {
    insert.bind_json(static_cast<int>(i + 1), flat[names[i]], names[i]);
  }
  insert.step();
  // A minimal runs entry (id only), so run_ids() also lists runs whose context was never added.
  Statement run(db_, path_,
                "INSERT OR IGNORE INTO runs (run_id, command, machine, device, git_commit, "
                "started, context) VALUES (?, '', ?, ?, ?, ?, '{}')");
  const std::string values[] = {row.run_id, row.machine, row.device, row.git_commit, row.timestamp};
  for (int i = 0; i < 5; ++i) run.bind_text(i + 1, values[i]);
  run.step();
}

std::vector<ResultRow> SqliteStore::select_rows(const std::string& sql, const std::string& bound) {
  Statement s(db_, path_, sql);
  if (!bound.empty()) s.bind_text(1, bound);
  std::vector<ResultRow> out;
  while (s.step()) {
    nlohmann::json flat = nlohmann::json::object();
    std::string id;
    for (int i = 0; i < sqlite3_column_count(s.get()); ++i) {
      const std::string name = sqlite3_column_name(s.get(), i);
      if (name == "id") {
        id = s.text(i);
        continue;
      }
      switch (sqlite3_column_type(s.get(), i)) {
        case SQLITE_INTEGER:
          flat[name] = static_cast<int64_t>(sqlite3_column_int64(s.get(), i));
          break;
        case SQLITE_FLOAT: {
          const double v = sqlite3_column_double(s.get(), i);
          flat[name] =
              std::isinf(v) && is_metric_column(name) ? nlohmann::json(nullptr) : nlohmann::json(v);
          break;
        }
        case SQLITE_NULL:
          break;  // absent, or another estimator's parameter/pass column
        default:
          flat[name] = s.text(i);
      }
    }
    out.push_back(unflatten(flat, "--db " + path_ + ": results[id=" + id + "]"));
  }
  return out;
}

std::vector<ResultRow> SqliteStore::all_rows() {
  return select_rows("SELECT * FROM results ORDER BY id", "");
}

std::vector<ResultRow> SqliteStore::rows_of_run(const std::string& run_id) {
  return select_rows("SELECT * FROM results WHERE run_id = ? ORDER BY id", run_id);
}

std::vector<RunContext> SqliteStore::runs() {
  Statement s(db_, path_,
              "SELECT run_id, command, machine, device, git_commit, started, context FROM runs "
              "ORDER BY started, rowid");
  std::vector<RunContext> out;
  while (s.step()) {
    nlohmann::json context = nlohmann::json::parse(s.text(6), nullptr, false);
    RunContext c = run_context_from_json(context.is_discarded() ? nlohmann::json() : context);
    c.run_id = s.text(0);
    c.command = s.text(1);
    c.machine = s.text(2);
    c.device = s.text(3);
    c.git_commit = s.text(4);
    c.started = s.text(5);
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<std::string> SqliteStore::run_ids() {
  std::vector<std::string> out;
  for (const RunContext& c : runs()) out.push_back(c.run_id);
  return out;
}

}  // namespace aoeval
