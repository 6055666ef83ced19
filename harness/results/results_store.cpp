// Results store: an output folder's results.csv + results.json, rewritten atomically after every
// row (results_store.h). The run context is run_context.cpp, the writers results_writers.cpp, the
// SQLite history results_sqlite.cpp.
#include "harness/results/results_store.h"

#include <climits>
#include <cstdint>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "base/errors.h"
#include "base/json_reader.h"
#include "base/text_files.h"

namespace aoeval {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- output folder

ResultsFolder::ResultsFolder(std::string dir, RunContext context, std::string stem)
    : dir_(std::move(dir)), stem_(std::move(stem)), context_(std::move(context)) {}

std::string ResultsFolder::csv_path() const {
  return (fs::path(dir_) / (stem_ + ".csv")).string();
}
std::string ResultsFolder::json_path() const {
  return (fs::path(dir_) / (stem_ + ".json")).string();
}

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
  std::vector<std::string> names;
  if (!fs::exists(path)) return names;
  std::vector<ResultRow> loaded = read_results_file(path, &existing_context_);
  for (const ResultRow& row : loaded) names.push_back(row.run_name);
  for (const ResultRow& row : rows_) {  // rows added before loading stay, after the loaded ones
    bool present = false;
    for (const ResultRow& l : loaded) present = present || l.run_name == row.run_name;
    if (!present) loaded.push_back(row);
  }
  rows_ = std::move(loaded);
  return names;
}

void ResultsFolder::merge(const ResultRow& row) {
  for (const ResultRow& r : rows_)
    if (r.run_name == row.run_name) return;
  rows_.push_back(row);
}

void ResultsFolder::add(const ResultRow& row) {
  bool replaced = false;
  for (ResultRow& r : rows_) {
    if (r.run_name == row.run_name) {
      r = row;
      replaced = true;
      break;
    }
  }
  if (!replaced) rows_.push_back(row);
  write();
}

void ResultsFolder::write() const {
  // JSON first: it is what --resume reads, so it never lags behind the CSV.
  write_text(json_path(), results_json(rows_, context_));
  write_text(csv_path(), results_csv(rows_));
}

}  // namespace aoeval
