// ResultRow <-> one flat JSON object whose keys are exactly the CSV/SQLite column names
// (CONTRACT §4 "Results"). Column order, as writers use it:
//   identifying_columns(): run_id, run_name, estimator, scene, view, width, height, definition,
//                          backend, status, params (the whole params object as a JSON string)
//   one column per parameter, named after it; a parameter named like a fixed column gets the
//                          prefix "param_" (e.g. a parameter "scene" -> column "param_scene")
//   measured_columns():    the metric keys, the same keys prefixed "true_", time_ms_median,
//                          time_ms_min, time_ms_max, repetitions, time_ms_samples (JSON
//                          array string), precompute_ms, reference (JSON
//                          string), machine, device, git_commit, aoeval_version, timestamp,
//                          estimate_file, timing_source
//   one column per pass, named by its pass_ms key as given (e.g. "horizon_ms")
// A metric absent from row.metrics is absent from the flat object (blank/NULL in the files); a
// metric present as null (psnr of identical images = +infinity) stays null. unflatten() takes the
// parameters from the `params` column; every other numeric key that is neither fixed nor a
// parameter column is a pass time. Null values of non-fixed keys are ignored (a union header
// leaves other estimators' parameter and pass columns blank/NULL).
#include "harness/results/result_row.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <stdexcept>

#include "harness/results/summary.h"

namespace aoeval {

namespace {

const std::vector<std::string>& metric_names() {
  static const std::vector<std::string> keys = {
      "pixels", "rmse", "mae", "bias", "max_abs", "p95_abs", "psnr", "ssim", "flip_mean",
      "ref_stderr_rms", "rmse_excess",
      // bent_metrics.h: blank without bent normals
      "bent_pixels", "bent_angle_mean", "bent_angle_p95", "bent_ref_stderr", "bent_angle_excess",
      // scoring/temporal.h (CONTRACT §10): blank for still views
      "seq_frames", "seq_rmse_excess", "steady_rmse_excess", "temporal_rmse",
      "temporal_rmse_excess", "converge_frames", "settle_frames", "disocclusion_rmse_excess"};
  return keys;
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

// The column of parameter `name`: its name, or "param_" + name where it would collide with a
// fixed column.
std::string parameter_column(const std::string& name) {
  return fixed_columns().count(name) ? "param_" + name : name;
}

std::string string_of(const nlohmann::json& flat, const char* key) {
  const auto it = flat.find(key);
  if (it == flat.end() || it->is_null()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

template <typename T>
T number_of(const nlohmann::json& flat, const char* key) {
  const auto it = flat.find(key);
  if (it == flat.end() || !it->is_number()) return T{};
  return it->get<T>();
}

// A JSON-valued column: stored as a JSON string, accepted as an object too.
nlohmann::json json_of(const nlohmann::json& flat, const char* key) {
  const auto it = flat.find(key);
  if (it == flat.end() || it->is_null()) return nlohmann::json::object();
  if (!it->is_string()) return *it;
  const std::string& text = it->get_ref<const std::string&>();
  if (text.empty()) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("results column ") + key + " is not JSON: " + e.what());
  }
}

}  // namespace

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
        "timestamp", "estimate_file", "timing_source"}) {
    columns.emplace_back(c);
  }
  return columns;
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
  flat["time_ms_median"] = row.time_ms_median;
  flat["time_ms_min"] = row.time_ms_min;
  flat["time_ms_max"] = row.time_ms_max;
  flat["repetitions"] = row.repetitions;
  flat["time_ms_samples"] = nlohmann::json(row.time_ms_samples).dump();
  flat["precompute_ms"] = row.precompute_ms;
  flat["reference"] = (row.reference.is_null() ? nlohmann::json::object() : row.reference).dump();
  flat["machine"] = row.machine;
  flat["device"] = row.device;
  flat["git_commit"] = row.git_commit;
  flat["aoeval_version"] = row.aoeval_version;
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

ResultRow unflatten(const nlohmann::json& flat) {
  if (!flat.is_object()) throw std::runtime_error("results row is not a JSON object");
  ResultRow row;
  row.run_id = string_of(flat, "run_id");
  row.run_name = string_of(flat, "run_name");
  row.estimator = string_of(flat, "estimator");
  row.scene = string_of(flat, "scene");
  row.view = string_of(flat, "view");
  row.width = number_of<int>(flat, "width");
  row.height = number_of<int>(flat, "height");
  row.definition = string_of(flat, "definition");
  row.backend = string_of(flat, "backend");
  row.status = flat.contains("status") ? string_of(flat, "status") : "ok";
  row.params = json_of(flat, "params");

  auto get_metrics = [&](const std::string& prefix) {
    nlohmann::json metrics = nlohmann::json::object();
    for (const auto& k : metric_names()) {
      const auto it = flat.find(prefix + k);
      if (it != flat.end()) metrics[k] = *it;
    }
    return metrics;
  };
  row.metrics = get_metrics("");
  row.true_metrics = get_metrics("true_");
  row.time_ms_median = number_of<double>(flat, "time_ms_median");
  row.time_ms_min = number_of<double>(flat, "time_ms_min");
  row.time_ms_max = number_of<double>(flat, "time_ms_max");
  row.repetitions = number_of<int>(flat, "repetitions");
  {
    const nlohmann::json samples = json_of(flat, "time_ms_samples");
    if (samples.is_array())
      for (const auto& v : samples)
        if (v.is_number()) row.time_ms_samples.push_back(v.get<double>());
  }
  row.precompute_ms = number_of<double>(flat, "precompute_ms");
  row.reference = json_of(flat, "reference");
  row.machine = string_of(flat, "machine");
  row.device = string_of(flat, "device");
  row.git_commit = string_of(flat, "git_commit");
  row.aoeval_version = string_of(flat, "aoeval_version");
  row.timestamp = string_of(flat, "timestamp");
  row.estimate_file = string_of(flat, "estimate_file");
  row.timing_source = string_of(flat, "timing_source");

  std::set<std::string> parameter_columns;
  if (row.params.is_object()) {
    for (const auto& item : row.params.items())
      parameter_columns.insert(parameter_column(item.key()));
  }
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
  return out;
}

}  // namespace aoeval
