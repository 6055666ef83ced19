#include "harness/results/point_record.h"

#include <cstdio>

#include "base/errors.h"
#include "harness/results/metric_table.h"

namespace aoeval {

const std::vector<std::string>& frame_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = {"frame", "time_ms", "disoccluded_pixels"};
    const std::vector<std::string> keys = metric_keys_of(MetricFamily::image);
    c.insert(c.end(), keys.begin(), keys.end());
    for (const auto& k : keys) c.push_back("true_" + k);
    return c;
  }();
  return columns;
}

nlohmann::json flatten(const FrameRow& frame) {
  nlohmann::json flat = {{"frame", frame.frame},
                         {"time_ms", frame.time_ms},
                         {"disoccluded_pixels", frame.disoccluded_pixels}};
  for (const auto& k : metric_keys_of(MetricFamily::image)) {
    if (const auto it = frame.metrics.find(k); it != frame.metrics.end()) flat[k] = *it;
    if (const auto it = frame.true_metrics.find(k); it != frame.true_metrics.end())
      flat["true_" + k] = *it;
  }
  return flat;
}

FrameRow frame_row(const nlohmann::json& flat, const std::string& where) {
  if (!flat.is_object()) throw InputError(where + ": not a JSON object");
  const auto number = [&](const std::string& key) -> const nlohmann::json* {
    const auto it = flat.find(key);
    if (it == flat.end()) return nullptr;
    if (!it->is_null() && !it->is_number())
      throw InputError(where + "." + key + ": not a number (" + it->dump() + ")");
    return &*it;
  };
  FrameRow f;
  const nlohmann::json* frame = number("frame");
  if (!frame || !frame->is_number_integer())
    throw InputError(where + ".frame: missing or not an integer");
  f.frame = frame->get<int>();
  if (const auto* t = number("time_ms"); t && !t->is_null()) f.time_ms = t->get<double>();
  if (const auto* d = number("disoccluded_pixels"); d && !d->is_null())
    f.disoccluded_pixels = d->get<int64_t>();
  for (const auto& k : metric_keys_of(MetricFamily::image)) {
    if (const auto* v = number(k)) f.metrics[k] = *v;
    if (const auto* v = number("true_" + k)) f.true_metrics[k] = *v;
  }
  return f;
}

std::vector<FrameRow> frame_rows(const std::vector<nlohmann::json>& flat) {
  std::vector<FrameRow> out;
  out.reserve(flat.size());
  for (size_t i = 0; i < flat.size(); ++i)
    out.push_back(frame_row(flat[i], "frames[" + std::to_string(i) + "]"));
  return out;
}

std::vector<nlohmann::json> flatten(const std::vector<FrameRow>& frames) {
  std::vector<nlohmann::json> out;
  out.reserve(frames.size());
  for (const FrameRow& f : frames) out.push_back(flatten(f));
  return out;
}

std::string frame_image_role(int frame, const std::string& what) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return std::string("frame ") + number + " " + what;
}

}  // namespace aoeval
