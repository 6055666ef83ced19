// Results store: an output folder's results.csv + results.json, rewritten atomically after every
// row (results_store.h). The run context is run_context.cpp, the writers results_writers.cpp, the
// SQLite history results_sqlite.cpp.
#include "harness/results/results_store.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "errors.h"
#include "json_reader.h"
#include "text_files.h"

namespace aoeval {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- output folder

ResultsFolder::ResultsFolder(std::string dir, RunContext context, std::string stem)
    : dir_(std::move(dir)), stem_(std::move(stem)), context_(std::move(context)) {
  fs::create_directories(dir_.empty() ? "." : dir_);
}

std::string ResultsFolder::csv_path() const {
  return (fs::path(dir_) / (stem_ + ".csv")).string();
}
std::string ResultsFolder::json_path() const {
  return (fs::path(dir_) / (stem_ + ".json")).string();
}

std::vector<std::string> ResultsFolder::load_existing() {
  const std::string path = json_path();
  std::vector<std::string> names;
  if (!fs::exists(path)) return names;
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  // Bad input, not our failure: a results file that is not ours, or was damaged by hand.
  const nlohmann::json j = parse_json_text(text.str(), path);
  if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array()) {
    throw InputError(path + ": rows: not a results file (no \"rows\" array)");
  }
  const int version = j.value("schema_version", 0);
  if (version > kResultsSchemaVersion) {
    throw InputError(path + ": schema_version " + std::to_string(version) +
                     " is newer than this aoeval's (" + std::to_string(kResultsSchemaVersion) +
                     ")");
  }
  std::vector<ResultRow> loaded;
  try {
    if (j.contains("context") && j["context"].is_object())
      existing_context_ = run_context_from_json(j["context"]);
    for (const auto& flat : j["rows"]) {
      loaded.push_back(unflatten(flat));
      names.push_back(loaded.back().run_name);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": rows: not a results file (" + e.what() + ")");
  }
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
