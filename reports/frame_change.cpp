#include "reports/frame_change.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace aoeval {

namespace {

std::optional<AccuracySample> frame_sample(const FrameRow& f) {
  AccuracySample s;
  const std::pair<const char*, double*> keys[] = {{"rmse_excess", &s.rmse_excess},
                                                  {"ref_stderr_rms", &s.ref_stderr_rms},
                                                  {"bias", &s.bias},
                                                  {"pixels", &s.pixels}};
  for (const auto& [key, value] : keys) {
    const auto it = f.metrics.find(key);
    if (it == f.metrics.end() || !it->is_number()) return std::nullopt;
    *value = it->get<double>();
  }
  return s;
}

}  // namespace

std::optional<FrameChange> frame_change(const std::vector<FrameRow>& before,
                                        const std::vector<FrameRow>& after, const Thresholds& t,
                                        bool same_ref) {
  std::map<int, AccuracySample> baseline;
  for (const FrameRow& f : before)
    if (const auto s = frame_sample(f)) baseline[f.frame] = *s;
  FrameChange change;
  double largest = -1.0;
  for (const FrameRow& f : after) {
    const auto a = frame_sample(f);
    const auto b = baseline.find(f.frame);
    if (!a || b == baseline.end()) continue;
    ++change.compared;
    const double sigma = accuracy_noise(b->second, *a, same_ref, std::nullopt).rmse_excess_sigma;
    const double limit = std::max({t.rmse_excess_relative * std::abs(b->second.rmse_excess),
                                   t.rmse_excess_sigmas * sigma, t.rmse_excess_absolute});
    const double moved = std::abs(a->rmse_excess - b->second.rmse_excess);
    if (!(moved > limit)) continue;
    ++change.changed;
    if (!change.spans.empty() && change.spans.back().second == f.frame - 1) {
      change.spans.back().second = f.frame;
    } else {
      change.spans.push_back({f.frame, f.frame});
    }
    if (moved > largest) {
      largest = moved;
      change.largest_frame = f.frame;
      change.largest_before = b->second.rmse_excess;
      change.largest_after = a->rmse_excess;
    }
  }
  if (change.compared < 2) return std::nullopt;
  return change;
}

std::string spans_text(const std::vector<std::pair<int, int>>& spans) {
  std::string out;
  for (const auto& [first, last] : spans) {
    if (!out.empty()) out += ", ";
    out += std::to_string(first);
    if (last != first) {  // appended in two steps: GCC 12's -Wrestrict misfires on "-" + string
      out += '-';
      out += std::to_string(last);
    }
  }
  return out;
}

}  // namespace aoeval
