// Cost-balanced shards (issue 19, CONTRACT §9). `--shard I/N` alone takes every N-th point, which
// is fair only when points cost the same; a suite's points differ by 100x (a 4096-ray path tracer
// next to a 4-direction SSAO). `aoeval sweep|run --slurm` therefore plans the shards: each point's
// cost is estimated, points are dealt largest first to the least-loaded shard (LPT, Graham 1969:
// within 4/3 of the optimum), and the plan is written to a file that every shard reads
// (`--shard I/N --shard-plan FILE`), so the shards agree on it whatever the node.
//
// The estimate of one point, in milliseconds:
//   cost = frames * frame_ms + precompute_ms + kScoringNsPerPixel * pixels
// with frames = warm-up + repetitions, and frame_ms and precompute_ms (prepare(): vertex-baked's
// bake, shader compiles) from the SQLite history, best source first:
//   "history" the medians of time_ms_median and precompute_ms of ok rows with the same run name
//             (same estimator, parameters, scene, view and resolution), on any machine;
//   "estimator" the median per-pixel frame time of the estimator's ok rows, times the pixels,
//             and its median precompute, each per unit of work, times the point's work (the
//             product of its ray-count parameters: a parameter whose unit is "rays" or
//             "directions"/"samples"/"steps"/"lights" scales the work; the precompute's scene
//             dependence, e.g. a bake's triangle count, is not modelled);
//   "default" kDefaultNsPerPixel per pixel and no precompute (no history: a new estimator).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "harness/results/result_row.h"
#include "harness/sweep/sweep_spec.h"

namespace aoeval {

// Per-pixel costs of what every point does besides its frames (G-buffer, scoring twice with SSIM
// and FLIP, the estimate EXR), and of a frame of an estimator without history. Measured on the
// default suite (README "Running on a cluster"); only ratios between points matter to the plan.
inline constexpr double kScoringNsPerPixel = 4000.0;
inline constexpr double kDefaultNsPerPixel = 2000.0;

struct PointCost {
  std::string name;
  double ms = 0.0;
  std::string source;  // "history", "estimator" or "default"
};

class CostModel {
 public:
  // `history`: rows of earlier runs (SqliteStore::all_rows()); may be empty.
  explicit CostModel(const std::vector<ResultRow>& history);
  PointCost estimate(const SweepPoint& point, const TimingSpec& timing) const;

 private:
  std::map<std::string, double> by_run_name_;             // median frame ms
  std::map<std::string, double> precompute_by_run_name_;  // median precompute ms
  std::map<std::string, double> ns_per_pixel_;         // estimator -> median ns per pixel per frame
  std::map<std::string, double> precompute_per_work_;  // estimator -> median precompute ms / work
};

// The product of a point's work-scaling parameters (see above), 1 when it has none.
double work_factor(const EstimatorInfo& estimator, const nlohmann::json& params);

struct ShardPlan {
  int shards = 1;
  std::vector<PointCost> points;  // every point, in expansion order
  std::vector<int> shard_of;      // per point
  std::vector<double> shard_ms;   // planned cost per shard
  // Slowest over mean planned shard cost (1 = perfectly balanced).
  double planned_ratio() const;
};

// LPT: largest cost first to the least-loaded shard (ties: lower shard index), deterministic.
ShardPlan plan_shards(const std::vector<PointCost>& points, int shards);

// plan.json: {"shards": N, "points": [{"name", "ms", "source", "shard"}], "shard_ms": [...]}.
void write_shard_plan(const std::string& path, const ShardPlan& plan);
// InputError naming the file and field when it is not a plan.
ShardPlan read_shard_plan(const std::string& path);

// The points the plan gives shard `index` of `count`, in expansion order. InputError when the
// plan was made for another shard count, or a point is missing from it (the spec changed after
// the plan was made) or the plan names a point the spec does not have.
std::vector<size_t> planned_shard(const ShardPlan& plan, const std::vector<std::string>& names,
                                  int index, int count, const std::string& plan_path);

}  // namespace aoeval

namespace aoeval {

// The indices of `names` (a sweep's or suite's points in expansion order) that `--shard SHARD`
// (I/N or auto; "" = every point) takes: with `plan_path`, the plan's shard I; without, every
// N-th point from I (CONTRACT §9). InputError for --shard-plan without --shard.
std::vector<size_t> shard_indices(const std::vector<std::string>& names, const std::string& shard,
                                  const std::string& plan_path);

}  // namespace aoeval
