// `aoeval bench rtao` and `aoeval bench temporal`: the cost per frame and per pass of an estimator
// that keeps state over a sequence (rtao: rays, temporal stage, variance, each a-trous pass; gtao
// or gtao-cpu with temporal=true: its passes and the shared stage's temporal_ms) on a
// static-camera sequence of one view (nothing moves: zero motion, nothing disoccluded, so every
// frame after 0 reprojects a full history, the steady state). Frame 0 (no history) is reported
// apart; the steady medians are over frames 1..F-1 of `repetitions` timed sequences, after
// `warmup` untimed ones; for rtao, the denoiser's cost (the median over those frames of temporal +
// variance + a-trous) and its ratio to the rays' median (csv row `denoiser`). Writes
// bench_<estimator>.md and .csv to --out, and one results row (status "timing only", its passes as
// columns) to results.csv/json and SQLite, as the other benches do.
#pragma once

#include <string>
#include <vector>

#include "base/default_paths.h"
#include "base/resolution.h"

namespace aoeval {

struct RtaoBenchOptions {
  std::string estimator = "rtao";  // any estimator that keeps state (EstimatorInfo::keeps_state)
  std::string scene = "bunny";
  std::string view;  // "" = the scene's first
  std::string res = kDefaultBenchResolution;
  int frames = 16;
  std::vector<std::string> sets;  // KEY=VALUE for rtao
  int warmup = 1;                 // untimed sequences first
  int repetitions = 3;            // timed sequences
  std::string out_dir = "out/bench-rtao";
  std::string database = kDefaultDatabase;
};

void bench_rtao(const RtaoBenchOptions& options);

}  // namespace aoeval
