// Results store: an output folder's results.csv + results.json, written whole or appended row by
// row with a journal (results_store.h). The run context is run_context.cpp, the writers
// results_writers.cpp, the SQLite history results_sqlite.cpp.
#include "harness/results/results_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "base/errors.h"
#include "base/json_reader.h"
#include "base/text_files.h"

namespace aoeval {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- output folder

ResultsFolder::ResultsFolder(std::string dir, RunContext context, std::string stem,
                             FolderWrites writes)
    : dir_(std::move(dir)), stem_(std::move(stem)), writes_(writes), context_(std::move(context)) {}

std::string ResultsFolder::csv_path() const {
  return (fs::path(dir_) / (stem_ + ".csv")).string();
}
std::string ResultsFolder::json_path() const {
  return (fs::path(dir_) / (stem_ + ".json")).string();
}
std::string ResultsFolder::journal_path() const {
  return (fs::path(dir_) / (stem_ + ".rows.jsonl")).string();
}

namespace {

// Appends `text` to `path` with one write (O_APPEND), so a kill leaves at most one partial line at
// the end, which load_existing() knows to ignore.
void append_text(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot append: " + std::strerror(errno));
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw std::runtime_error(path + ": cannot append: " + why);
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) throw std::runtime_error(path + ": cannot append: " + std::strerror(errno));
}

// The journal's rows in order. A last line without its newline is an append cut short by a kill:
// left out unless it holds the whole object (its row is in SQLite, which is written first, or the
// point runs again). Any other unreadable line is an InputError naming the file and the line.
std::vector<ResultRow> read_journal(const std::string& path) {
  std::vector<ResultRow> rows;
  std::error_code ec;
  if (!fs::exists(path, ec)) return rows;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  size_t start = 0, line = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    const bool cut = end == std::string::npos;
    if (cut) end = text.size();
    ++line;
    const std::string where = path + ": line " + std::to_string(line);
    const nlohmann::json flat = nlohmann::json::parse(text.substr(start, end - start), nullptr,
                                                      /*allow_exceptions=*/false);
    if (flat.is_discarded() || !flat.is_object()) {
      if (cut) break;
      throw InputError(where + ": not a results row (one JSON object a line)");
    }
    rows.push_back(unflatten(flat, where));
    start = end + 1;
  }
  return rows;
}

}  // namespace

std::vector<ResultRow> read_results_file(const std::string& path,
                                         std::optional<RunContext>* context) {
  // Bad input, not our failure: a results file that is not ours, or was damaged by hand. Every
  // problem is named by the file and the field ("results.json: rows[2].run_name: ...").
  const nlohmann::json j = parse_json_file(path);
  if (!j.is_object() || !j.contains("rows"))
    throw InputError(path + ": rows: not a results file (no \"rows\" array)");
  JsonReader root(j, path);
  const int64_t version = root.integer("schema_version", 0, 0, INT32_MAX);
  if (version > kResultsSchemaVersion) {
    throw InputError(path + ": schema_version " + std::to_string(version) +
                     " is newer than this aoeval's (" + std::to_string(kResultsSchemaVersion) +
                     ")");
  }
  const nlohmann::json& rows = root.raw("rows");
  if (!rows.is_array()) root.fail("rows", "expected an array of results rows");
  if (auto c = root.optional_object("context"); c && context) {
    try {
      *context = run_context_from_json(c->json());
    } catch (const nlohmann::json::exception& e) {
      std::string what = e.what();
      if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
      root.fail("context", what);
    }
  }
  std::vector<ResultRow> loaded;
  std::set<std::string> names;
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::string where = path + ": rows[" + std::to_string(i) + "]";
    loaded.push_back(unflatten(rows[i], where));
    if (!names.insert(loaded.back().run_name).second)
      throw InputError(where + ".run_name: \"" + loaded.back().run_name +
                       "\" is also an earlier row's (each point has one row)");
  }
  return loaded;
}

std::vector<std::string> ResultsFolder::load_existing() {
  const std::string path = json_path();
  std::vector<ResultRow> loaded;
  if (fs::exists(path)) loaded = read_results_file(path, &existing_context_);
  std::vector<ResultRow> journal = read_journal(journal_path());
  std::vector<ResultRow> held = std::move(rows_);
  rows_.clear();
  index_.clear();
  columns_ = ResultColumns();
  files_current_ = false;
  std::vector<std::string> names;
  for (std::vector<ResultRow>* from : {&loaded, &journal})
    for (const ResultRow& row : *from)
      if (!put(row)) names.push_back(row.run_name);
  for (const ResultRow& row : held) merge(row);  // rows added before loading stay, after these
  return names;
}

bool ResultsFolder::put(const ResultRow& row) {
  const auto [it, added] = index_.try_emplace(row.run_name, rows_.size());
  if (added) {
    rows_.push_back(row);
  } else {
    rows_[it->second] = row;
  }
  columns_.add(row);
  return !added;
}

void ResultsFolder::merge(const ResultRow& row) {
  if (!index_.count(row.run_name)) put(row);
}

void ResultsFolder::add(const ResultRow& row) {
  const bool replaced = put(row);
  if (writes_ == FolderWrites::whole || !files_current_) {
    write();
    return;
  }
  const nlohmann::json flat = flatten(row);
  append_text(journal_path(), flat.dump() + "\n");
  // A new column changes the header, a replaced row a line in the middle: the CSV is rewritten
  // (a sweep brings its columns with its first rows; a row is replaced only when retimed).
  const std::vector<std::string> columns = columns_.list();
  if (replaced || columns != csv_columns_) {
    write_text(csv_path(), results_csv(rows_));
    csv_columns_ = columns;
  } else {
    append_text(csv_path(), csv_line(flat, csv_columns_) + "\n");
  }
}

void ResultsFolder::write() {
  // JSON first: it is what --resume reads, so it never lags behind the CSV; the journal goes last,
  // once the JSON holds its rows.
  write_text(json_path(), results_json(rows_, context_));
  write_text(csv_path(), results_csv(rows_));
  csv_columns_ = columns_.list();
  std::error_code ec;
  fs::remove(journal_path(), ec);
  if (ec) throw std::runtime_error(journal_path() + ": cannot remove: " + ec.message());
  files_current_ = true;
}

}  // namespace aoeval
