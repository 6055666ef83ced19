// `aoeval bench shadowmap`: shadowmap-ao's (GPU Gems ch. 17 §17.3) cost against the number of
// lights and the shadow-map resolution, per pass (GPU timestamps): the shadow maps (n renders of
// the scene) and the accumulation (n shadow tests per receiver). Writes bench_shadowmap.csv and
// bench_shadowmap.md to --out, and results rows (results.csv/json, SQLite) like `bench estimators`.
#pragma once

#include <string>
#include <vector>

#include "base/default_paths.h"

namespace aoeval {

struct ShadowmapBenchOptions {
  std::string scene = "bunny";
  std::string res = "320x240";
  std::vector<int> lights{64, 128, 256, 512};
  std::vector<int> resolutions{128, 256, 512};
  std::vector<std::string> sets;  // further KEY=VALUE for shadowmap-ao
  int warmup = 1;
  int repetitions = 3;
  std::string out_dir = "out/bench-shadowmap";
  std::string database = kDefaultDatabase;
};

void bench_shadowmap(const ShadowmapBenchOptions& options);

}  // namespace aoeval
