// Sweep specifications (CONTRACT §5): scenes x views x runs, each run an estimator with a grid (a
// Cartesian product; a key may take a list or {"range": [lo, hi, steps], "scale": "lin|log"}) and
// fixed parameters. Expansion order is deterministic, so shards and resumes agree on it.
#pragma once

#include <string>
#include <vector>

#include "harness/evaluation/evaluation.h"

namespace aoeval {

struct SweepPoint {
  const EstimatorInfo* estimator = nullptr;
  nlohmann::json overrides = nlohmann::json::object();  // grid values + fixed values
  std::string scene, view;
  int width = 0, height = 0;
  std::string name;            // the row's run name
  bool seed_per_frame = true;  // sequence views (CONTRACT §10)
};

// What the evaluation session runs for a point.
EvaluationRequest evaluation_request(const SweepPoint& p);

struct SweepSpec {
  std::string name;
  std::vector<std::string> scenes;
  bool all_views = false;
  std::vector<std::string> views;  // when !all_views; empty = each scene's first view
  int width = 0, height = 0;       // 0 = each view's own
  ReferenceSpec reference;
  TimingSpec timing;
  struct Run {
    const EstimatorInfo* estimator = nullptr;
    std::vector<std::pair<std::string, std::vector<nlohmann::json>>> grid;  // declaration order
    nlohmann::json fixed = nlohmann::json::object();
    bool seed_per_frame = true;  // "seed_per_frame": false keeps one seed for every frame
  };
  std::vector<Run> runs;
};

// Parses and validates a spec; every error names the file and the field (unknown keys, unknown
// estimators, unknown or out-of-range parameters, a key in both grid and fixed).
SweepSpec parse_sweep_spec(const nlohmann::json& spec, const std::string& file);
SweepSpec load_sweep_spec(const std::string& path);

// The values of one grid entry: a list, or a range expanded linearly or logarithmically (integer
// parameters are rounded and deduplicated). Errors read "<file>: <path>.<key>: ...", path being
// the entry's field path ("runs[0].grid.radius").
std::vector<nlohmann::json> expand_grid_values(const ParamSpec& param, const nlohmann::json& entry,
                                               const std::string& file, const std::string& path);

// A sweep larger than this is almost always a typo in a range (two 100,000-step ranges make 1e10
// points and would run for years with no output); `aoeval sweep --max-points N` raises it. The
// paper suite, the largest shipped, has under 2,000.
inline constexpr size_t kDefaultMaxSweepPoints = 100000;

// Every point, in order: runs, then grid points (the last key varies fastest), then scenes, then
// views. Scenes are loaded only to list their views when "views" is "all". InputError, before
// anything is expanded, when the grid would give more than `max_points` points, and when two
// different scene files share a name (their rows would collapse into one point).
std::vector<SweepPoint> expand_sweep(const SweepSpec& spec,
                                     size_t max_points = kDefaultMaxSweepPoints);

// Shard I of N (0-based): every N-th point starting at I. The shards' union is the whole sweep and
// they are disjoint.
std::vector<SweepPoint> select_shard(const std::vector<SweepPoint>& points, int index, int count);
// "I/N" -> {I, N}; "auto" reads SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT (CONTRACT §9);
// InputError for anything else, or for "auto" outside a Slurm job array.
std::pair<int, int> parse_shard(const std::string& text);

}  // namespace aoeval
