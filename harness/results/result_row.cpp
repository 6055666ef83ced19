// ResultRow <-> one flat JSON object whose keys are exactly the CSV/SQLite column names
// (CONTRACT §4 "Results"). Column order, as writers use it:
//   identifying_columns(): run_id, run_name, estimator, scene, view, width, height, definition,
//                          backend, status, params (the whole params object as a JSON string)
//   one column per parameter, named after it; a parameter named like a fixed column gets the
//                          prefix "param_" (e.g. a parameter "scene" -> column "param_scene")
//   measured_columns():    the metric keys, the same keys prefixed "true_", time_ms_median,
//                          time_ms_min, time_ms_max, repetitions, time_ms_samples (JSON
//                          array string), precompute_ms, reference (JSON
//                          string), machine, device, git_commit, aoeval_version,
//                          estimator_version, timestamp, estimate_file, timing_source
//   one column per pass, named by its pass_ms key as given (e.g. "horizon_ms")
// A metric absent from row.metrics is absent from the flat object (blank/NULL in the files); a
// metric present as null (psnr of identical images = +infinity) stays null. unflatten() takes the
// parameters from the `params` column; every other numeric key that is neither fixed nor a
// parameter column is a pass time. Null values of non-fixed keys are ignored (a union header
// leaves other estimators' parameter and pass columns blank/NULL).
#include "harness/results/result_row.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <type_traits>

#include "base/errors.h"
#include "base/hash.h"
#include "base/summary.h"
#include "harness/results/metric_table.h"

namespace aoeval {

namespace {

// Every metric column (metric_table.h, bent and sequence keys blank where they do not apply).
const std::vector<std::string>& metric_names() {
  return all_metric_keys();
}

// The column of parameter `name`: its name, or "param_" + name where it would collide with a
// fixed column.
std::string parameter_column(const std::string& name) {
  return fixed_columns().count(name) ? "param_" + name : name;
}

// Every row read from disk (results.json, the SQLite history) passes through unflatten(), which
// checks it here, column by column: a hand-edited or foreign file fails with its place named
// ("results.json: rows[1].run_name: ...") instead of becoming a blank row or a raw library error.
class FlatRow {
 public:
  FlatRow(const nlohmann::json& flat, const std::string& where) : flat_(flat), where_(where) {}

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    throw InputError(where_ + (key.empty() ? "" : "." + key) + ": " + problem);
  }
  // nullptr when absent or null (blank in CSV, NULL in SQLite).
  const nlohmann::json* find(const std::string& key) const {
    const auto it = flat_.find(key);
    return it == flat_.end() || it->is_null() ? nullptr : &*it;
  }
  std::string text(const char* key, bool required = false) const {
    const nlohmann::json* v = find(key);
    if (!v) {
      if (required) fail(key, "required field is missing");
      return "";
    }
    if (!v->is_string()) fail(key, "expected a string, got " + describe(*v));
    if (required && v->get_ref<const std::string&>().empty()) fail(key, "must not be empty");
    return v->get<std::string>();
  }
  template <typename T>
  T number(const char* key) const {
    const nlohmann::json* v = find(key);
    if (!v) return T{};
    if (std::is_integral_v<T> ? !v->is_number_integer() : !v->is_number())
      fail(key, std::string("expected ") + (std::is_integral_v<T> ? "an integer" : "a number") +
                    ", got " + describe(*v));
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < 0.0 || d > static_cast<double>(std::numeric_limits<T>::max()))
      fail(key, "value " + describe(*v) + " is out of range");
    return v->get<T>();
  }
  // A JSON-valued column of `kind` (object or array): stored as JSON text, accepted as the value.
  nlohmann::json json(const char* key, nlohmann::json::value_t kind) const {
    const nlohmann::json* v = find(key);
    nlohmann::json out =
        kind == nlohmann::json::value_t::array ? nlohmann::json::array() : nlohmann::json::object();
    if (!v) return out;
    if (v->is_string()) {
      const std::string& text = v->get_ref<const std::string&>();
      if (text.empty()) return out;
      out = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
      if (out.is_discarded()) fail(key, "is not JSON text");
    } else {
      out = *v;
    }
    if (out.type() != kind)
      fail(key, std::string("expected ") +
                    (kind == nlohmann::json::value_t::array ? "an array" : "an object") + ", got " +
                    describe(out));
    return out;
  }
  // Metrics hold a number, or null for +infinity (psnr of identical images).
  void check_metric(const std::string& key, const nlohmann::json& v) const {
    if (!v.is_null() && !v.is_number()) fail(key, "expected a number or null, got " + describe(v));
  }

 private:
  static std::string describe(const nlohmann::json& v) {
    std::string s = v.dump();
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
  }
  const nlohmann::json& flat_;
  const std::string& where_;
};

}  // namespace

const std::vector<std::string>& sequence_metric_names() {
  static const std::vector<std::string> keys = metric_keys_of(MetricFamily::sequence);
  return keys;
}

std::vector<std::string> identifying_columns() {
  return {"run_id", "run_name",   "estimator", "scene",  "view",  "width",
          "height", "definition", "backend",   "status", "params"};
}

std::vector<std::string> measured_columns() {
  std::vector<std::string> columns = metric_names();
  for (const auto& k : metric_names()) columns.push_back("true_" + k);
  for (const char* c :
       {"time_ms_median", "time_ms_min", "time_ms_max", "repetitions", "time_ms_samples",
        "precompute_ms", "reference", "machine", "device", "git_commit", "aoeval_version",
        "estimator_version", "timestamp", "estimate_file", "timing_source"}) {
    columns.emplace_back(c);
  }
  return columns;
}

const std::set<std::string>& fixed_columns() {
  static const std::set<std::string> fixed = [] {
    std::set<std::string> s;
    for (const auto& c : identifying_columns()) s.insert(c);
    for (const auto& c : measured_columns()) s.insert(c);
    return s;
  }();
  return fixed;
}

nlohmann::json flatten(const ResultRow& row) {
  nlohmann::json flat = nlohmann::json::object();
  flat["run_id"] = row.run_id;
  flat["run_name"] = row.run_name;
  flat["estimator"] = row.estimator;
  flat["scene"] = row.scene;
  flat["view"] = row.view;
  flat["width"] = row.width;
  flat["height"] = row.height;
  flat["definition"] = row.definition;
  flat["backend"] = row.backend;
  flat["status"] = row.status;
  const nlohmann::json params = row.params.is_null() ? nlohmann::json::object() : row.params;
  if (!params.is_object()) throw std::invalid_argument("results row params is not a JSON object");
  flat["params"] = params.dump();

  for (const auto& [name, value] : params.items()) {
    const std::string column = parameter_column(name);
    if (flat.contains(column)) {
      throw std::invalid_argument("parameters \"" + name + "\" and \"" + column +
                                  "\" both map to results column " + column);
    }
    flat[column] = value;
  }
  auto put_metrics = [&](const nlohmann::json& metrics, const std::string& prefix) {
    if (!metrics.is_object()) return;
    for (const auto& k : metric_names()) {
      const auto it = metrics.find(k);
      if (it != metrics.end()) flat[prefix + k] = *it;
    }
  };
  put_metrics(row.metrics, "");
  put_metrics(row.true_metrics, "true_");
  // A row never timed (skipped: no repetition) has no times: blank in CSV, null in JSON and NULL
  // in SQLite, never a 0 ms that a chart or a sort would take for a measurement.
  const bool timed = row.repetitions > 0 || !row.time_ms_samples.empty();
  const auto time_cell = [&](double v) {
    return timed ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  flat["time_ms_median"] = time_cell(row.time_ms_median);
  flat["time_ms_min"] = time_cell(row.time_ms_min);
  flat["time_ms_max"] = time_cell(row.time_ms_max);
  flat["repetitions"] = row.repetitions;
  flat["time_ms_samples"] = nlohmann::json(row.time_ms_samples).dump();
  flat["precompute_ms"] = time_cell(row.precompute_ms);
  flat["reference"] = (row.reference.is_null() ? nlohmann::json::object() : row.reference).dump();
  flat["machine"] = row.machine;
  flat["device"] = row.device;
  flat["git_commit"] = row.git_commit;
  flat["aoeval_version"] = row.aoeval_version;
  flat["estimator_version"] = row.estimator_version;
  flat["timestamp"] = row.timestamp;
  flat["estimate_file"] = row.estimate_file;
  flat["timing_source"] = row.timing_source;

  for (const auto& [pass, ms] : row.pass_ms) {
    if (fixed_columns().count(pass) || flat.contains(pass)) {
      throw std::invalid_argument("pass time \"" + pass +
                                  "\" collides with a results column of the same name");
    }
    flat[pass] = ms;
  }
  return flat;
}

ResultRow unflatten(const nlohmann::json& flat, const std::string& where) {
  if (!flat.is_object()) {
    std::string got = flat.dump();
    if (got.size() > 40) got = got.substr(0, 37) + "...";
    throw InputError(where + ": expected a results row (a JSON object), got " + got);
  }
  const FlatRow f(flat, where);
  ResultRow row;
  row.run_id = f.text("run_id");
  row.run_name = f.text("run_name", /*required=*/true);
  row.estimator = f.text("estimator", /*required=*/true);
  row.scene = f.text("scene");
  row.view = f.text("view");
  row.width = f.number<int>("width");
  row.height = f.number<int>("height");
  row.definition = f.text("definition");
  row.backend = f.text("backend");
  row.status = f.find("status") ? f.text("status") : "ok";
  row.params = f.json("params", nlohmann::json::value_t::object);

  auto get_metrics = [&](const std::string& prefix) {
    nlohmann::json metrics = nlohmann::json::object();
    for (const auto& k : metric_names()) {
      const auto it = flat.find(prefix + k);
      if (it == flat.end()) continue;
      f.check_metric(prefix + k, *it);
      metrics[k] = *it;
    }
    return metrics;
  };
  row.metrics = get_metrics("");
  row.true_metrics = get_metrics("true_");
  row.time_ms_median = f.number<double>("time_ms_median");
  row.time_ms_min = f.number<double>("time_ms_min");
  row.time_ms_max = f.number<double>("time_ms_max");
  row.repetitions = f.number<int>("repetitions");
  for (const auto& v : f.json("time_ms_samples", nlohmann::json::value_t::array)) {
    if (!v.is_number()) f.fail("time_ms_samples", "expected numbers, got " + v.dump());
    row.time_ms_samples.push_back(v.get<double>());
  }
  row.precompute_ms = f.number<double>("precompute_ms");
  row.reference = f.json("reference", nlohmann::json::value_t::object);
  row.machine = f.text("machine");
  row.device = f.text("device");
  row.git_commit = f.text("git_commit");
  row.aoeval_version = f.text("aoeval_version");
  row.estimator_version = f.text("estimator_version");  // absent in older files: ""
  row.timestamp = f.text("timestamp");
  row.estimate_file = f.text("estimate_file");
  row.timing_source = f.text("timing_source");

  std::set<std::string> parameter_columns;
  for (const auto& item : row.params.items())
    parameter_columns.insert(parameter_column(item.key()));
  for (const auto& [key, value] : flat.items()) {
    if (value.is_number() && !fixed_columns().count(key) && !parameter_columns.count(key)) {
      row.pass_ms[key] = value.get<double>();
    }
  }
  return row;
}

void ResultRow::set_times(const std::vector<double>& samples_ms) {
  time_ms_median = median(samples_ms);
  time_ms_min = samples_ms.empty() ? 0.0 : *std::min_element(samples_ms.begin(), samples_ms.end());
  time_ms_max = samples_ms.empty() ? 0.0 : *std::max_element(samples_ms.begin(), samples_ms.end());
  repetitions = static_cast<int>(samples_ms.size());
  time_ms_samples = samples_ms;
}

std::string file_stem_for(const std::string& run_name) {
  std::string out;
  for (char c : run_name) {
    if (c == '/') {
      out += "__";
    } else if (c == ':') {
      out += '-';
    } else if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_') {
      out += c;
    } else {
      out += '_';
    }
  }
  // The readable part is lossy (view "a<b" and "a>b" both read "a_b", "a:b" reads like "a-b"):
  // a hash of the whole name beside it keeps one file per point (issue 48).
  char hash[16];
  std::snprintf(hash, sizeof hash, "_%08x", static_cast<unsigned>(fnv1a(run_name) & 0xffffffffu));
  return out + hash;
}

void check_file_stems(const std::vector<std::string>& run_names, const std::string& where) {
  std::map<std::string, const std::string*> owner;
  for (const auto& name : run_names) {
    const auto [it, fresh] = owner.emplace(file_stem_for(name), &name);
    if (!fresh && *it->second != name)
      throw InputError(where + ": points \"" + *it->second + "\" and \"" + name +
                       "\" would share the file name " + it->first +
                       "; rename a view, scene or estimator");
  }
}

}  // namespace aoeval
