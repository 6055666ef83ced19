// `aoeval figures`: reproductions of the seed papers' figures and tables. A figure is a name, the
// paper and figure number, the paper's claim, and a function that measures our numbers through the
// harness (EvaluationSession, the estimator registry) and writes <out>/<name>.png (plus any extra
// images). The command writes the numbers as <name>.csv and the caption as <name>.txt; the
// caption's verdict comes from checks computed on those numbers (verdict_of), never from a fixed
// string.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "harness/evaluation/evaluation.h"

namespace aoeval::figures {

// One testable statement of the claim, evaluated on our numbers. `rule` says what must hold and
// with which threshold ("systematic RMSE < random RMSE at 16 rays"); `measured` gives the numbers.
struct Check {
  std::string rule;
  bool passed = false;
  std::string measured;
};

enum class Verdict { reproduced, partly_reproduced, not_reproduced };
const char* verdict_name(Verdict v);  // "reproduced", "partly reproduced", "not reproduced"
// The rule every caption states: every check holds -> reproduced; some but not all -> partly
// reproduced; none (or no check could be made) -> not reproduced.
Verdict verdict_of(const std::vector<Check>& checks);
inline constexpr const char* kVerdictRule =
    "reproduced when every check holds, partly reproduced when some do, not reproduced when none "
    "do";

// The numbers behind a figure: one header, rows of text cells (numbers already formatted).
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  void add(std::vector<std::string> row);  // std::invalid_argument when the width differs
};
std::string to_csv(const Table& t);              // RFC 4180 quoting where a cell needs it
std::string fmt(double v, int significant = 4);  // "%.*g"; "nan"/"inf" spelled out

struct FigureResult {
  std::vector<Check> checks;
  std::string measured;             // what we ran: scenes, resolutions, settings, reference
  std::vector<std::string> notes;   // caveats: skipped estimators, substitutions
  Table table;                      // written as <name>.csv
  std::vector<std::string> images;  // files written under the output folder (first = <name>.png)
};

struct FigureContext {
  std::string out_dir;
  bool quick = false;  // tiny resolutions and few repetitions: for tests
  EvaluationSession* session = nullptr;
  // A resolution scaled for --quick: full size normally, `quick` otherwise.
  int pick(int full, int quick_value) const { return quick ? quick_value : full; }
  std::string path(const std::string& file) const;  // out_dir / file
};

struct Figure {
  std::string name;    // "hegeman-fig2"
  std::string source;  // "Hegeman et al. 2006, Fig. 2"
  std::string claim;   // the paper's claim with its numbers, quoted or paraphrased
  std::function<FigureResult(FigureContext&)> make;
};

// Every figure, in the order `--all` runs them.
const std::vector<Figure>& figure_registry();
const Figure* find_figure(const std::string& name);  // nullptr when unknown

// The per-paper lists figure_registry() concatenates.
std::vector<Figure> hegeman_figures();
std::vector<Figure> mendez_figures();
std::vector<Figure> gpugems_figures();
std::vector<Figure> dimitrov_figures();
std::vector<Figure> equal_time_figures();  // ours: figures_equal_time.cpp
std::vector<Figure> engine_figures();      // ours, issue 32: figures_engine.cpp
std::vector<Figure> temporal_figures();    // ours, issue 31: figures_temporal.cpp

// The caption text: source, claim, what we measured, each check, the verdict and its rule, notes.
std::string caption_text(const Figure& f, const FigureResult& r);

}  // namespace aoeval::figures
