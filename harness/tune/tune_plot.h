// tune.png (CONTRACT §8): the objective by evaluation, with the best feasible value so far, and
// the error against time with the Pareto front and the budget, side by side; drawn through the
// shared drawing code (drawing/plot.h), so tune.png.plot.json keeps the plotted data.
#pragma once

#include <string>
#include <vector>

#include "harness/tune/tune_spec.h"

namespace aoeval {

struct TunePlotPoint {
  double objective = 0.0;                                      // as the metric reads
  double time_ms = 0.0, time_ms_min = 0.0, time_ms_max = 0.0;  // means over views
  // The timing noise where the front is decided: the mean over views of pareto_time_noise() of
  // each view's row, as the report judges a row (harness/results/pareto.h).
  double time_ms_noise = 0.0;
  bool feasible = true;
  bool best = false;
};

// Points in evaluation order (evaluations whose rows were skipped left out).
void render_tune_plot(const TuneSpec& spec, const std::vector<TunePlotPoint>& points,
                      const std::string& out_png);

}  // namespace aoeval
