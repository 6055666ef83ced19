// Suites (`aoeval run --suite NAME|FILE.json`): a suite is a JSON file holding a list of CONTRACT
// §5 sweep specifications (or one specification), so users read and edit suites in the format they
// already know. The shipped suites are harness/suites/{quick,default,paper}.json.
//
// Within a suite, a run without a "grid" is an estimator's featured point (its mosaic is shown in
// the report); a run with a grid is its sweep (plotted as error against time). Points that compute
// the same thing (same estimator, effective parameters, scene, view, resolution, reference and
// timing) run once, where the first is listed; it is featured if any of them is.
#pragma once

#include <string>
#include <vector>

#include "harness/sweep/sweep_spec.h"

namespace aoeval {

struct Suite {
  std::string name;  // "default", or the file's stem for a suite given by path
  std::string path;  // the file it was read from
  std::vector<SweepSpec> specs;
};

// "quick" -> <source>/harness/suites/quick.json; anything ending in ".json" or holding a '/' is a
// path. An unknown name is an InputError listing the shipped suites.
std::string suite_file(const std::string& name_or_path);
std::vector<std::string> shipped_suites();
Suite load_suite(const std::string& name_or_path);
// `doc` is a list of sweep specs or one sweep spec; errors name `file` and the spec.
Suite parse_suite(const nlohmann::json& doc, const std::string& file, const std::string& name);

// `--set ESTIMATOR:KEY=VALUE`: the value replaces KEY's grid or fixed value in every run of
// ESTIMATOR in the suite. InputError (naming it) for a malformed assignment, an unknown estimator,
// an estimator the suite does not run, an unknown key or an invalid value.
struct SuiteOverride {
  std::string estimator, key, value;
};
SuiteOverride parse_suite_override(const std::string& text);
void apply_suite_overrides(Suite& suite, const std::vector<SuiteOverride>& overrides);

struct SuitePoint {
  SweepPoint point;
  size_t spec = 0;        // index into Suite::specs (its reference and timing apply)
  bool featured = false;  // from a run without a grid (see above)
};

// Every point of every spec, in order, duplicates removed (see above). When an (estimator, scene,
// view) has no featured point, its first point is featured, so every pairing gets a mosaic.
std::vector<SuitePoint> expand_suite(const Suite& suite);

}  // namespace aoeval
