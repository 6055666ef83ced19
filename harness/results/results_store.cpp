// Results store: run context, output folder (results.csv + results.json), SQLite history and
// the text writers. See results_store.h for the formats and the SQLite schema.
#include "harness/results/results_store.h"

#include <sqlite3.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "exr_io.h"

#if __has_include(<embree3/rtcore_config.h>)
#include <embree3/rtcore_config.h>
#endif
#if __has_include("version.h")
#include "version.h"
#include "harness/results/summary.h"
#endif

namespace aoeval {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- run context

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const size_t begin = line.find_first_not_of(" \t", colon + 1);
    return begin == std::string::npos ? "unknown CPU" : line.substr(begin);
  }
  return "unknown CPU";
}

std::string git_commit() {
#ifdef AOEVAL_SOURCE_DIR
  std::string dir = AOEVAL_SOURCE_DIR, quoted = "'";
  for (char c : dir) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  FILE* pipe = popen(("git -C " + quoted + " rev-parse HEAD 2>/dev/null").c_str(), "r");
  if (!pipe) return "unknown";
  char buffer[128] = {};
  std::string out = std::fgets(buffer, sizeof buffer, pipe) ? buffer : "";
  pclose(pipe);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  const bool hex =
      out.size() >= 40 && out.find_first_not_of("0123456789abcdef") == std::string::npos;
  return hex ? out : "unknown";
#else
  return "unknown";
#endif
}

}  // namespace

RunContext make_run_context(const std::string& command) {
  RunContext c;
  char suffix[8];
  std::snprintf(suffix, sizeof suffix, "%06x", std::random_device{}() & 0xffffffu);
  c.run_id = utc_now("%Y%m%dT%H%M%SZ") + "-" + suffix;
  c.command = command;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "unknown-host");
  const std::string cpu = cpu_model();
  c.machine = std::string(host) + " (" + cpu + ", " +
              std::to_string(std::thread::hardware_concurrency()) + " cores)";
  c.device = cpu;
#ifdef RTC_VERSION_STRING
  c.embree_version = RTC_VERSION_STRING;
#else
  c.embree_version = "unknown";
#endif
  c.git_commit = git_commit();
#if __has_include("version.h")
  c.aoeval_version = kAoevalVersion;
#elif defined(AOEVAL_VERSION)
  c.aoeval_version = AOEVAL_VERSION;
#else
  c.aoeval_version = "unknown";
#endif
  c.started = utc_now("%Y-%m-%dT%H:%M:%SZ");
  return c;
}

nlohmann::json to_json(const RunContext& c) {
  return {{"run_id", c.run_id},
          {"command", c.command},
          {"machine", c.machine},
          {"device", c.device},
          {"embree_version", c.embree_version},
          {"git_commit", c.git_commit},
          {"aoeval_version", c.aoeval_version},
          {"started", c.started},
          {"output_dir", c.output_dir}};
}

RunContext run_context_from_json(const nlohmann::json& j) {
  auto s = [&](const char* key) { return j.is_object() ? j.value(key, std::string()) : ""; };
  return {s("run_id"),     s("command"),        s("machine"), s("device"),    s("embree_version"),
          s("git_commit"), s("aoeval_version"), s("started"), s("output_dir")};
}

// ---------------------------------------------------------------- columns and cells

namespace {

const std::set<std::string>& fixed_set() {
  static const std::set<std::string> fixed = [] {
    std::set<std::string> s;
    for (const auto& c : identifying_columns()) s.insert(c);
    for (const auto& c : measured_columns()) s.insert(c);
    return s;
  }();
  return fixed;
}

void append_unique(std::vector<std::string>& out, std::set<std::string>& seen,
                   const std::string& c) {
  if (seen.insert(c).second) out.push_back(c);
}

std::string shortest(double v) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

// A cell for tables read by people: integers whole, other numbers to 4 significant digits.
std::string readable(const nlohmann::json& v, const std::string& column) {
  if (v.is_null()) return is_metric_column(column) ? "inf" : "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return v.dump();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.4g", d);
    if (std::isfinite(d) && std::fabs(d) >= 1e4 && std::fabs(d) < 1e15) {
      std::snprintf(buffer, sizeof buffer, "%.0f", d);
    }
    return buffer;
  }
  return v.dump();
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> cells;
  std::vector<bool> numeric;  // per column: every non-empty value is a number
};

Table make_table(const std::vector<ResultRow>& rows, const std::vector<std::string>& columns) {
  Table t{columns, {}, std::vector<bool>(columns.size(), true)};
  for (const ResultRow& row : rows) {
    const nlohmann::json flat = flatten(row);
    std::vector<std::string> line;
    for (size_t i = 0; i < columns.size(); ++i) {
      const auto it = flat.find(columns[i]);
      if (it == flat.end()) {
        line.emplace_back();
        continue;
      }
      if (!it->is_number() && !(it->is_null() && is_metric_column(columns[i]))) {
        t.numeric[i] = false;
      }
      line.push_back(readable(*it, columns[i]));
    }
    t.cells.push_back(std::move(line));
  }
  return t;
}

size_t display_width(const std::string& s) {
  size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;  // count UTF-8 code points
  return n;
}

}  // namespace

bool is_metric_column(const std::string& column) {
  static const std::set<std::string> metrics = [] {
    std::set<std::string> s;
    for (const auto& c : measured_columns()) {
      if (c.rfind("time_ms", 0) == 0) break;  // metrics and true_ metrics come first
      s.insert(c);
    }
    return s;
  }();
  return metrics.count(column) > 0;
}

std::vector<std::string> result_columns(const std::vector<ResultRow>& rows) {
  std::vector<std::string> out = identifying_columns();
  std::set<std::string> seen(out.begin(), out.end());
  std::vector<std::string> passes;
  std::set<std::string> seen_passes;
  for (const ResultRow& row : rows) {
    const nlohmann::json flat = flatten(row);  // kept alive: items() does not own it
    for (const auto& item : flat.items()) {
      if (fixed_set().count(item.key()) || row.pass_ms.count(item.key())) continue;
      append_unique(out, seen, item.key());
    }
    for (const auto& [pass, ms] : row.pass_ms) append_unique(passes, seen_passes, pass);
  }
  for (const auto& c : measured_columns()) append_unique(out, seen, c);
  for (const auto& c : passes) append_unique(out, seen, c);
  return out;
}

// ---------------------------------------------------------------- writers

namespace {
std::string csv_cell(const nlohmann::json& v, const std::string& column) {
  std::string text;
  if (v.is_null()) {
    text = is_metric_column(column) ? "inf" : "";
  } else if (v.is_string()) {
    text = v.get<std::string>();
  } else if (v.is_boolean()) {
    text = v.get<bool>() ? "true" : "false";
  } else if (v.is_number_integer()) {
    text = v.dump();
  } else if (v.is_number_float()) {
    text = shortest(v.get<double>());
  } else {
    text = v.dump();
  }
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}
}  // namespace

std::string results_csv(const std::vector<ResultRow>& rows) {
  const std::vector<std::string> columns = result_columns(rows);
  std::string out;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';  // appends, not "," + string: GCC 12 warns falsely (-Wrestrict, PR 105329)
    out += csv_cell(columns[i], "");
  }
  out += "\n";
  for (const ResultRow& row : rows) {
    const nlohmann::json flat = flatten(row);
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i) out += ",";
      const auto it = flat.find(columns[i]);
      if (it != flat.end()) out += csv_cell(*it, columns[i]);
    }
    out += "\n";
  }
  return out;
}

std::string results_json(const std::vector<ResultRow>& rows, const RunContext& context) {
  const std::vector<std::string> columns = result_columns(rows);
  nlohmann::ordered_json out;
  out["schema_version"] = kResultsSchemaVersion;
  out["context"] = {{"run_id", context.run_id},
                    {"command", context.command},
                    {"machine", context.machine},
                    {"device", context.device},
                    {"embree_version", context.embree_version},
                    {"git_commit", context.git_commit},
                    {"aoeval_version", context.aoeval_version},
                    {"started", context.started},
                    {"output_dir", context.output_dir}};
  out["rows"] = nlohmann::ordered_json::array();
  for (const ResultRow& row : rows) {
    const nlohmann::json flat = flatten(row);
    nlohmann::ordered_json ordered = nlohmann::ordered_json::object();
    for (const auto& c : columns) {
      const auto it = flat.find(c);
      if (it != flat.end()) ordered[c] = *it;
    }
    out["rows"].push_back(std::move(ordered));
  }
  return out.dump(2) + "\n";
}

std::string markdown_table(const std::vector<ResultRow>& rows,
                           const std::vector<std::string>& columns) {
  const Table t = make_table(rows, columns);
  auto escape = [](const std::string& s) {
    std::string e;
    for (char c : s)
      e += c == '|' ? std::string("\\|") : (c == '\n' || c == '\r') ? " " : std::string(1, c);
    return e;
  };
  std::string out = "|";
  for (const auto& h : t.header) out.append(" ").append(escape(h)).append(" |");
  out += "\n|";
  for (size_t i = 0; i < t.header.size(); ++i) out += t.numeric[i] ? "---:|" : "---|";
  out += "\n";
  for (const auto& line : t.cells) {
    out += "|";
    for (const auto& cell : line) out.append(" ").append(escape(cell)).append(" |");
    out += "\n";
  }
  return out;
}

std::string console_table(const std::vector<ResultRow>& rows,
                          const std::vector<std::string>& columns) {
  const Table t = make_table(rows, columns);
  std::vector<size_t> width(columns.size());
  for (size_t i = 0; i < columns.size(); ++i) {
    width[i] = display_width(t.header[i]);
    for (const auto& line : t.cells) width[i] = std::max(width[i], display_width(line[i]));
  }
  auto format_line = [&](const std::vector<std::string>& line) {
    std::string out;
    for (size_t i = 0; i < line.size(); ++i) {
      const std::string pad(width[i] - display_width(line[i]), ' ');
      out += (i ? "  " : "") + (t.numeric[i] ? pad + line[i] : line[i] + pad);
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out + "\n";
  };
  std::string out = format_line(t.header);
  std::vector<std::string> rule;
  for (size_t w : width) rule.emplace_back(w, '-');
  out += format_line(rule);
  for (const auto& line : t.cells) out += format_line(line);
  return out;
}

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
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": not JSON: " + e.what());
  }
  if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array()) {
    throw std::runtime_error(path + ": not a results file (no \"rows\" array)");
  }
  const int version = j.value("schema_version", 0);
  if (version > kResultsSchemaVersion) {
    throw std::runtime_error(path + ": schema version " + std::to_string(version) +
                             " is newer than this aoeval's (" +
                             std::to_string(kResultsSchemaVersion) + ")");
  }
  std::vector<ResultRow> loaded;
  for (const auto& flat : j["rows"]) {
    loaded.push_back(unflatten(flat));
    names.push_back(loaded.back().run_name);
  }
  for (const ResultRow& row : rows_) {  // rows added before loading stay, after the loaded ones
    bool present = false;
    for (const ResultRow& l : loaded) present = present || l.run_name == row.run_name;
    if (!present) loaded.push_back(row);
  }
  rows_ = std::move(loaded);
  return names;
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
