// Plots for reports and paper figures, drawn by matplotlib (Debian's python3-matplotlib): a
// well-kept plotting library with proper axes, log scales, legends and error bars, instead of
// hand-drawn pixels. C++ describes the plot as data (PlotSpec); reports/plot.py draws it. The
// spec is also kept beside the image (<out>.plot.json) so every figure can be redrawn or audited.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace aoeval {

struct PlotSeries {
  std::string label;            // legend entry ("" = none)
  std::string kind = "line";    // "line", "scatter", "step" or "bar"
  std::vector<double> x, y;     // bar: x are category indices 0..n-1 (see PlotSpec::categories)
  std::vector<double> y_error;  // optional, same length as y: symmetric error bars
  std::vector<bool> highlight;  // optional, same length as y: marked points (Pareto front)
  std::vector<std::string> point_labels;  // optional, same length as y: annotated next to points
  std::string colour;  // optional matplotlib colour ("C0", "#d62728"); "" = cycle
  std::string marker;  // optional ("o", "s", "^", ...); "" = default for the kind
  bool dashed = false;
};

struct PlotSpec {
  std::string title;
  std::string x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<std::string> categories;  // bar charts: the x tick labels
  std::vector<PlotSeries> series;
  std::vector<std::string> notes;          // lines of text drawn in the lower corner of the axes
  double width_in = 7.0, height_in = 4.5;  // figure size in inches
  int dpi = 110;
  // When not empty, the figure is these plots side by side (each its own axes: title, labels,
  // series, notes), and this spec's own series are not drawn; its size and dpi apply.
  std::vector<PlotSpec> panels;
};

// Writes the plot to `out_path` (.png or .svg, chosen by the extension) atomically, plus
// `out_path + ".plot.json"`. Throws std::runtime_error with the reason (python3 or matplotlib
// missing, plot.py's error message) when it cannot.
void render_plot(const PlotSpec& spec, const std::string& out_path);
// Several plots from one python process (matplotlib's import, about half a second, paid once;
// a pre-started worker's when one is idle, see plot_workers.h); otherwise as render_plot. Throws on
// the first plot that fails; those before it are written.
void render_plots(const std::vector<std::pair<PlotSpec, std::string>>& plots);
// The same, split over one python process per core (plot i drawn by process i mod cores, each
// through render_plots): starting Python and importing matplotlib costs about as much as drawing
// a chart, so a process per chart spent half the report's time starting interpreters (issue 16),
// and one process for all of a report's charts leaves the other cores idle (issue 42: the default
// suite's 33 sequence charts took 3.3 s of one core). Throws the first failure's message after
// every share has been tried.
void render_plots_on_every_core(const std::vector<std::pair<PlotSpec, std::string>>& plots);

// The python interpreter used: $AOEVAL_PYTHON, else /usr/bin/python3 (Debian's, which has
// python3-matplotlib), else python3 on PATH.
std::string plot_python();
// The drawing script: $AOEVAL_PLOT_SCRIPT, else drawing/plot.py in the source tree.
std::string plot_script();

}  // namespace aoeval
