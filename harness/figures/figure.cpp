#include "harness/figures/figure.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace aoeval::figures {

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::reproduced:
      return "reproduced";
    case Verdict::partly_reproduced:
      return "partly reproduced";
    case Verdict::not_reproduced:
      return "not reproduced";
  }
  return "not reproduced";
}

Verdict verdict_of(const std::vector<Check>& checks) {
  size_t passed = 0;
  for (const auto& c : checks) passed += c.passed ? 1 : 0;
  if (passed == 0) return Verdict::not_reproduced;
  return passed == checks.size() ? Verdict::reproduced : Verdict::partly_reproduced;
}

void Table::add(std::vector<std::string> row) {
  if (row.size() != columns.size())
    throw std::invalid_argument("table row has " + std::to_string(row.size()) + " cells for " +
                                std::to_string(columns.size()) + " columns");
  rows.push_back(std::move(row));
}

namespace {
std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}
}  // namespace

std::string to_csv(const Table& t) {
  std::ostringstream os;
  for (size_t i = 0; i < t.columns.size(); ++i) os << (i ? "," : "") << csv_cell(t.columns[i]);
  os << '\n';
  for (const auto& row : t.rows) {
    for (size_t i = 0; i < row.size(); ++i) os << (i ? "," : "") << csv_cell(row[i]);
    os << '\n';
  }
  return os.str();
}

std::string fmt(double v, int significant) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", significant, v);
  return buf;
}

std::string FigureContext::path(const std::string& file) const {
  return (std::filesystem::path(out_dir) / file).string();
}

const std::vector<Figure>& figure_registry() {
  static const std::vector<Figure> registry = [] {
    std::vector<Figure> all;
    for (auto list : {hegeman_figures(), mendez_figures(), gpugems_figures(), dimitrov_figures(),
                      equal_time_figures(), engine_figures(), temporal_figures()})
      for (auto& f : list) all.push_back(std::move(f));
    return all;
  }();
  return registry;
}

const Figure* find_figure(const std::string& name) {
  for (const auto& f : figure_registry())
    if (f.name == name) return &f;
  return nullptr;
}

std::string caption_text(const Figure& f, const FigureResult& r) {
  std::ostringstream os;
  os << f.name << " — " << f.source << "\n\n";
  os << "Claim: " << f.claim << "\n\n";
  os << "Measured: " << r.measured << "\n\n";
  os << "Checks:\n";
  for (const auto& c : r.checks)
    os << "  [" << (c.passed ? "pass" : "fail") << "] " << c.rule << ": " << c.measured << "\n";
  if (r.checks.empty()) os << "  (none could be made)\n";
  os << "\nVerdict: " << verdict_name(verdict_of(r.checks)) << " (" << kVerdictRule << ").\n";
  if (!r.notes.empty()) {
    os << "\nNotes:\n";
    for (const auto& n : r.notes) os << "  - " << n << "\n";
  }
  return os.str();
}

}  // namespace aoeval::figures
