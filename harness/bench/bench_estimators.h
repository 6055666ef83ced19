// `aoeval bench estimators`: a timing table (median/min/max ms and Mpixel/s) of estimators on
// scenes, on the console and as CSV and Markdown; the rows also go to results.csv/json and SQLite.
#pragma once

#include <string>
#include <vector>

#include "base/default_paths.h"
#include "base/resolution.h"

namespace aoeval {

struct EstimatorBenchOptions {
  std::vector<std::string> scenes{"bunny"};
  std::vector<std::string> estimators;  // empty = all
  std::vector<std::string> sets;        // KEY=VALUE, applied to estimators that have the key
  std::string res = kDefaultBenchResolution;
  int warmup = 1;
  int repetitions = 5;
  std::string out_dir = "out/bench";
  std::string database = kDefaultDatabase;
};

void bench_estimators(const EstimatorBenchOptions& options);

}  // namespace aoeval
