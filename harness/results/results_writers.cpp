// The text writers of result rows (results_store.h): the column order, CSV, JSON, Markdown and
// console tables. Each reads the same ResultRows; none runs or stores anything.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "base/errors.h"
#include "harness/results/results_store.h"

namespace aoeval {

// ---------------------------------------------------------------- columns and cells

namespace {

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

bool ResultColumns::add(const ResultRow& row) {
  const size_t before = params_.size() + passes_.size();
  const nlohmann::json flat = flatten(row);  // kept alive: items() does not own it
  for (const auto& item : flat.items()) {
    if (fixed_columns().count(item.key()) || row.pass_ms.count(item.key())) continue;
    append_unique(params_, seen_params_, item.key());
  }
  for (const auto& [pass, ms] : row.pass_ms) append_unique(passes_, seen_passes_, pass);
  return params_.size() + passes_.size() != before;
}

std::vector<std::string> ResultColumns::list() const {
  std::vector<std::string> out = identifying_columns();
  std::set<std::string> seen(out.begin(), out.end());
  for (const auto& c : params_) append_unique(out, seen, c);
  for (const auto& c : measured_columns()) append_unique(out, seen, c);
  for (const auto& c : passes_) append_unique(out, seen, c);
  return out;
}

std::vector<std::string> result_columns(const std::vector<ResultRow>& rows) {
  ResultColumns columns;
  for (const ResultRow& row : rows) columns.add(row);
  return columns.list();
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

std::string csv_line(const nlohmann::json& flat, const std::vector<std::string>& columns) {
  std::string out;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';  // appends, not "," + string: GCC 12 warns falsely (-Wrestrict, PR 105329)
    const auto it = flat.find(columns[i]);
    if (it != flat.end()) out += csv_cell(*it, columns[i]);
  }
  return out;
}

std::string results_csv(const std::vector<ResultRow>& rows) {
  const std::vector<std::string> columns = result_columns(rows);
  std::string out;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';
    out += csv_cell(columns[i], "");
  }
  out += "\n";
  for (const ResultRow& row : rows) out += csv_line(flatten(row), columns) + "\n";
  return out;
}

std::string frames_csv(const std::vector<nlohmann::json>& frames) {
  std::vector<std::string> columns = {"frame", "time_ms", "disoccluded_pixels"};
  std::set<std::string> seen(columns.begin(), columns.end());
  for (const auto& c : measured_columns())
    for (const auto& f : frames)
      if (f.contains(c) && seen.insert(c).second) {
        columns.push_back(c);
        break;
      }
  for (const auto& f : frames)
    for (const auto& [key, value] : f.items())
      if (seen.insert(key).second) columns.push_back(key);
  std::string out;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) out += ',';
    out += csv_cell(columns[i], "");
  }
  out += "\n";
  for (const auto& f : frames) {
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i) out += ",";
      const auto it = f.find(columns[i]);
      if (it != f.end()) out += csv_cell(*it, columns[i]);
    }
    out += "\n";
  }
  return out;
}

std::string frames_csv_path(const std::string& out_dir, const std::string& run_name) {
  return out_dir + "/sequences/" + file_stem_for(run_name) + "/frames.csv";
}

std::vector<nlohmann::json> read_frames_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::vector<std::string> header;
  std::vector<nlohmann::json> frames;
  std::string line;
  const auto cells = [](const std::string& text) {
    std::vector<std::string> out(1);
    for (char c : text) {
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    }
    return out;
  };
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = path + ":" + std::to_string(number);
    if (number == 1) {
      header = cells(line);
      if (header.front() != "frame")
        throw InputError(path + ": not a frames.csv (its header does not begin with frame)");
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> values = cells(line);
    if (values.size() != header.size())
      throw InputError(where + ": " + std::to_string(values.size()) + " cells under a header of " +
                       std::to_string(header.size()));
    nlohmann::json flat = nlohmann::json::object();
    for (size_t i = 0; i < values.size(); ++i) {
      const std::string& v = values[i];
      if (v.empty()) continue;
      if (v == "inf" && is_metric_column(header[i])) {
        flat[header[i]] = nullptr;
        continue;
      }
      const char* end = v.data() + v.size();
      int64_t integer = 0;
      if (auto [p, ec] = std::from_chars(v.data(), end, integer); ec == std::errc() && p == end) {
        flat[header[i]] = integer;
        continue;
      }
      double real = 0.0;
      if (auto [p, ec] = std::from_chars(v.data(), end, real); ec == std::errc() && p == end) {
        flat[header[i]] = real;
        continue;
      }
      throw InputError(where + ": " + header[i] + " is not a number (" + v + ")");
    }
    frames.push_back(std::move(flat));
  }
  if (header.empty()) throw InputError(path + ": empty (a frames.csv has a header line)");
  return frames;
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
  if (!context.stages_ms.empty())
    out["context"]["stages_ms"] = nlohmann::ordered_json::parse(context.stages_ms.dump());
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
  for (size_t r = 0; r < rows.size(); ++r) {
    // A skipped row has no metrics: its name and why, not a line of blanks.
    if (rows[r].status != "ok") {
      out += (rows[r].run_name.empty() ? rows[r].estimator : rows[r].run_name) + "  " +
             rows[r].status + "\n";
      continue;
    }
    out += format_line(t.cells[r]);
  }
  return out;
}

}  // namespace aoeval
