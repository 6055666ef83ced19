// `aoeval dashboard --history N` (CONTRACT §12): every row of the judged run is a series over the
// last N runs of its suite or sweep (matched by run name), for three figures, each searched for
// steps by reports/change_points.h with the noise model its kind needs:
//   rmse_excess      tolerance: max(rmse_excess_relative x level, rmse_excess_absolute,
//                    rmse_excess_sigmas x the reference-noise sigma of regression.h), the sigma
//                    0 when every run scored against the same reference (it then cancels)
//   other keys       every other key the metric table flags for the dashboard that the newest row
//                    carries (the sequence keys): the same with the key's MetricRule and
//                    metric_noise_sigma (regression.h)
//   mean             mean AO of the estimate image; tolerance change_mean_shift (the same row and
//                    seed repeat bit for bit, so anything beyond it moved)
//   time_ms_median   permutation test at time_alpha with the magnitude floor time_relative, over
//                    the runs measured on the newest row's machine class only
#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "harness/results/machine_class.h"
#include "reports/change_points.h"
#include "reports/dashboard.h"
#include "reports/regression_config.h"

namespace aoeval {

namespace {

using RunRows = std::pair<RunContext, std::vector<ResultRow>>;

const ResultRow* row_named(const std::vector<ResultRow>& rows, const std::string& run_name) {
  for (const auto& r : rows)
    if (r.run_name == run_name && r.status == "ok") return &r;
  return nullptr;
}

// The mean AO of a row's estimate, read once per (run, row); NaN when the image is not there.
double history_mean_ao(Dashboard& d, const RunContext& run, const ResultRow& row) {
  const std::string key = run.run_id + "|" + row.run_name;
  if (const auto it = d.mean_ao.find(key); it != d.mean_ao.end()) return it->second;
  double mean = std::nan("");
  const std::string path = estimate_path(row, run);
  if (!path.empty()) {
    try {
      mean = mean_ao(read_planes(path));
    } catch (const InputError&) {
      // an image deleted or unreadable: that run has no point in the mean-AO series
    }
  }
  d.mean_ao[key] = mean;
  return mean;
}

double metric_of(const ResultRow& r, const std::string& key) {
  const auto it = r.metrics.find(key);
  return it != r.metrics.end() && it->is_number() ? it->get<double>() : std::nan("");
}

}  // namespace

void find_steps(Dashboard& d, const std::vector<RunRows>& history, const RegressionConfig& config) {
  for (const RowReport& rep : d.rows) {
    if (!rep.after || rep.after->status != "ok") continue;
    const ResultRow& newest = *rep.after;
    const Thresholds t = config.thresholds(rep.estimator, rep.scene);
    std::vector<std::string> figures = {"rmse_excess"};
    for (const std::string& key : rule_metric_keys())
      if (std::isfinite(metric_of(newest, key))) figures.push_back(key);
    figures.push_back("mean");
    figures.push_back("time_ms_median");
    for (const std::string& f : figures) {
      const bool rule_key = f != "rmse_excess" && f != "mean" && f != "time_ms_median";
      std::vector<double> values;
      std::vector<size_t> runs;  // history index of each value
      bool one_reference = true;
      double sigma = 0.0;
      for (size_t i = 0; i < history.size(); ++i) {
        const ResultRow* r = row_named(history[i].second, newest.run_name);
        if (!r) continue;
        double v = std::nan("");
        if (f == "rmse_excess") {
          v = metric_of(*r, f);
          one_reference = one_reference && same_reference(*r, newest);
          if (const auto s = accuracy_sample(*r)) sigma = std::max(sigma, rmse_excess_sigma(*s));
        } else if (rule_key) {
          v = metric_of(*r, f);
          one_reference = one_reference && same_reference(*r, newest);
          sigma = std::max(sigma, metric_noise_sigma(f, *r));
        } else if (f == "mean") {
          v = history_mean_ao(d, history[i].first, *r);
        } else if (machine_class(*r) == machine_class(newest) && r->time_ms_median > 0.0) {
          v = r->time_ms_median;
        }
        if (!std::isfinite(v)) continue;
        values.push_back(v);
        runs.push_back(i);
      }
      ChangePointOptions o;
      if (f == "rmse_excess") {
        o.relative = t.rmse_excess_relative;
        // Two independent references: the difference's sigma is sqrt(2) times one row's.
        o.absolute = std::max(t.rmse_excess_absolute,
                              one_reference ? 0.0 : t.rmse_excess_sigmas * std::sqrt(2.0) * sigma);
      } else if (rule_key) {
        const MetricRule rule = t.rule(f);
        o.relative = rule.relative;
        o.absolute =
            std::max(rule.absolute, one_reference ? 0.0 : rule.sigmas * std::sqrt(2.0) * sigma);
      } else if (f == "mean") {
        o.absolute = t.change_mean_shift;
      } else {
        o.test = ChangePointOptions::Test::permutation;
        o.relative = t.time_relative;
        o.alpha = t.time_alpha;
        // Enough permutations that p can reach alpha with one permutation as large.
        o.permutations = std::max(199, static_cast<int>(std::ceil(2.0 / t.time_alpha)) - 1);
      }
      for (const ChangePoint& cp : change_points(values, o)) {
        SeriesStep s;
        s.series = newest.run_name;
        s.estimator = rep.estimator;
        s.scene = rep.scene;
        s.figure = f;
        s.run = history[runs[cp.index]].first;
        s.before = cp.before;
        s.after = cp.after;
        s.p = cp.p;
        d.steps.push_back(s);
      }
    }
  }
}

}  // namespace aoeval
