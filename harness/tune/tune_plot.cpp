#include "harness/tune/tune_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "drawing/plot.h"
#include "harness/results/pareto.h"

namespace aoeval {

namespace {

PlotSeries series(std::string label, std::string kind, std::string colour) {
  PlotSeries s;
  s.label = std::move(label);
  s.kind = std::move(kind);
  s.colour = std::move(colour);
  return s;
}

}  // namespace

void render_tune_plot(const TuneSpec& spec, const std::vector<TunePlotPoint>& points,
                      const std::string& out_png) {
  PlotSpec figure;
  figure.width_in = 12.0;
  figure.height_in = 4.5;

  PlotSpec by_eval;
  by_eval.title = spec.name + ": " + spec.objective + " by evaluation";
  by_eval.x_label = "evaluation";
  by_eval.y_label = spec.objective + " (mean over views)";
  PlotSeries feasible = series("feasible", "scatter", "C0");
  PlotSeries infeasible = series("over the budget", "scatter", "0.6");
  PlotSeries so_far = series("best feasible so far", "step", "C3");
  infeasible.marker = "x";
  double best = spec.maximise ? -std::numeric_limits<double>::infinity()
                              : std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    PlotSeries& s = p.feasible ? feasible : infeasible;
    s.x.push_back(static_cast<double>(i));
    s.y.push_back(p.objective);
    if (p.feasible)
      best = spec.maximise ? std::max(best, p.objective) : std::min(best, p.objective);
    if (std::isfinite(best)) {
      so_far.x.push_back(static_cast<double>(i));
      so_far.y.push_back(best);
    }
  }
  for (auto* s : {&feasible, &infeasible, &so_far})
    if (!s->x.empty()) by_eval.series.push_back(*s);
  by_eval.log_y = !spec.maximise;

  PlotSpec by_time;
  by_time.title = "error against time";
  by_time.x_label = "frame time, ms (mean over views of the median)";
  by_time.y_label = spec.objective;
  by_time.log_x = true;
  by_time.log_y = !spec.maximise;
  // The Pareto front over every evaluated point, by the report's rule (harness/results/pareto.h;
  // a maximised objective is negated into an error).
  PlotSeries all = series("evaluations", "scatter", "C0");
  std::vector<double> cost, error, noise;
  for (const auto& p : points) {
    cost.push_back(p.time_ms);
    error.push_back(spec.maximise ? -p.objective : p.objective);
    noise.push_back(p.time_ms_noise);
    all.x.push_back(p.time_ms);
    all.y.push_back(p.objective);
  }
  for (const bool on_front : pareto_front(cost, error, noise)) all.highlight.push_back(on_front);
  by_time.series.push_back(all);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : points) {
    lo = std::min(lo, p.objective);
    hi = std::max(hi, p.objective);
  }
  if (spec.budget_ms > 0.0) {
    PlotSeries budget =
        series("budget " + format_param_value(spec.budget_ms) + " ms", "line", "C3");
    budget.x = {spec.budget_ms, spec.budget_ms};
    budget.y = {lo, hi};
    budget.dashed = true;
    budget.marker = "none";
    by_time.series.push_back(budget);
  }
  for (const auto& p : points) {
    if (!p.best) continue;
    PlotSeries b = series("best feasible", "scatter", "C3");
    b.x = {p.time_ms};
    b.y = {p.objective};
    b.marker = "*";
    by_time.series.push_back(b);
    char note[160];
    std::snprintf(note, sizeof note, "best %s %.4g at %.4g ms", spec.objective.c_str(), p.objective,
                  p.time_ms);
    by_eval.notes.push_back(note);
  }
  figure.panels = {by_eval, by_time};
  render_plot(figure, out_png);
}

}  // namespace aoeval
