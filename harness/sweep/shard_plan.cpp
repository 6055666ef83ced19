#include "harness/sweep/shard_plan.h"

#include <algorithm>
#include <fstream>
#include <set>

#include "base/errors.h"
#include "base/summary.h"
#include "estimators/registry.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace {

bool scales_work(const std::string& unit) {
  static const std::set<std::string> units = {"rays",    "directions", "steps",
                                              "samples", "lights",     "taps"};
  return units.count(unit) > 0;
}

}  // namespace

double work_factor(const EstimatorInfo& estimator, const nlohmann::json& params) {
  double factor = 1.0;
  for (const ParamSpec& p : estimator.params) {
    if (p.type != ParamType::integer || !scales_work(p.unit)) continue;
    const nlohmann::json& v = params.contains(p.name) ? params.at(p.name) : p.default_value;
    if (v.is_number()) factor *= std::max(1.0, v.get<double>());
  }
  return factor;
}

CostModel::CostModel(const std::vector<ResultRow>& history) {
  std::map<std::string, std::vector<double>> frames, precompute, per_pixel, precompute_per_work;
  for (const ResultRow& r : history) {
    if (r.status != "ok" || r.time_ms_median <= 0.0 || r.width <= 0 || r.height <= 0) continue;
    frames[r.run_name].push_back(r.time_ms_median);
    precompute[r.run_name].push_back(r.precompute_ms);
    const double pixels = static_cast<double>(r.width) * r.height;
    double w = 1.0;
    for (const EstimatorInfo& e : estimator_registry())  // history may name a gone plug-in
      if (e.name == r.estimator) w = work_factor(e, r.params);
    per_pixel[r.estimator].push_back(r.time_ms_median * 1e6 / pixels / w);
    precompute_per_work[r.estimator].push_back(r.precompute_ms / w);
  }
  for (auto& [k, v] : frames) by_run_name_[k] = median(v);
  for (auto& [k, v] : precompute) precompute_by_run_name_[k] = median(v);
  for (auto& [k, v] : per_pixel) ns_per_pixel_[k] = median(v);
  for (auto& [k, v] : precompute_per_work) precompute_per_work_[k] = median(v);
}

PointCost CostModel::estimate(const SweepPoint& p, const TimingSpec& timing) const {
  PointCost c;
  c.name = p.name;
  const double pixels = static_cast<double>(std::max(1, p.width)) * std::max(1, p.height);
  const double frames = timing.warmup + timing.repetitions;
  double frame_ms = 0.0, precompute_ms = 0.0;
  if (auto it = by_run_name_.find(p.name); it != by_run_name_.end()) {
    frame_ms = it->second;
    precompute_ms = precompute_by_run_name_.at(p.name);
    c.source = "history";
  } else if (auto e = ns_per_pixel_.find(p.estimator->name); e != ns_per_pixel_.end()) {
    const ParamSet params =
        resolve_params(p.estimator->name, p.estimator->params, p.overrides, p.name);
    const double w = work_factor(*p.estimator, params.json());
    frame_ms = e->second * pixels * w * 1e-6;
    precompute_ms = precompute_per_work_.at(p.estimator->name) * w;
    c.source = "estimator";
  } else {
    frame_ms = kDefaultNsPerPixel * pixels * 1e-6;
    c.source = "default";
  }
  c.ms = frames * frame_ms + precompute_ms + kScoringNsPerPixel * pixels * 1e-6;
  return c;
}

double ShardPlan::planned_ratio() const {
  if (shard_ms.empty()) return 1.0;
  double sum = 0.0, most = 0.0;
  for (double v : shard_ms) {
    sum += v;
    most = std::max(most, v);
  }
  return sum > 0.0 ? most / (sum / static_cast<double>(shard_ms.size())) : 1.0;
}

ShardPlan plan_shards(const std::vector<PointCost>& points, int shards) {
  ShardPlan plan;
  plan.shards = shards;
  plan.points = points;
  plan.shard_of.assign(points.size(), 0);
  plan.shard_ms.assign(static_cast<size_t>(shards), 0.0);
  std::vector<size_t> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return points[a].ms > points[b].ms; });
  for (size_t i : order) {
    const auto least = std::min_element(plan.shard_ms.begin(), plan.shard_ms.end());
    plan.shard_of[i] = static_cast<int>(least - plan.shard_ms.begin());
    *least += points[i].ms;
  }
  return plan;
}

void write_shard_plan(const std::string& path, const ShardPlan& plan) {
  nlohmann::json j;
  j["shards"] = plan.shards;
  j["planned_ratio"] = plan.planned_ratio();
  j["shard_ms"] = plan.shard_ms;
  nlohmann::json pts = nlohmann::json::array();
  for (size_t i = 0; i < plan.points.size(); ++i)
    pts.push_back({{"name", plan.points[i].name},
                   {"ms", plan.points[i].ms},
                   {"source", plan.points[i].source},
                   {"shard", plan.shard_of[i]}});
  j["points"] = pts;
  write_text(path, j.dump(1) + "\n");
}

ShardPlan read_shard_plan(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the shard plan");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  ShardPlan plan;
  try {
    plan.shards = j.at("shards").get<int>();
    plan.shard_ms = j.at("shard_ms").get<std::vector<double>>();
    for (const auto& p : j.at("points")) {
      plan.points.push_back({p.at("name").get<std::string>(), p.at("ms").get<double>(),
                             p.at("source").get<std::string>()});
      plan.shard_of.push_back(p.at("shard").get<int>());
    }
  } catch (const std::exception& e) {
    throw InputError(path + ": not a shard plan (" + e.what() + ")");
  }
  if (plan.shards < 1) throw InputError(path + ": shards: must be at least 1");
  return plan;
}

std::vector<size_t> planned_shard(const ShardPlan& plan, const std::vector<std::string>& names,
                                  int index, int count, const std::string& plan_path) {
  if (count != plan.shards)
    throw InputError(plan_path + ": shards: the plan has " + std::to_string(plan.shards) +
                     " shards, --shard asks for " + std::to_string(count));
  std::map<std::string, int> shard_of;
  for (size_t i = 0; i < plan.points.size(); ++i) shard_of[plan.points[i].name] = plan.shard_of[i];
  std::vector<size_t> selected;
  for (size_t i = 0; i < names.size(); ++i) {
    const auto it = shard_of.find(names[i]);
    if (it == shard_of.end())
      throw InputError(plan_path + ": points: no entry for " + names[i] +
                       " (the spec changed after the plan was made; plan again)");
    if (it->second == index) selected.push_back(i);
    shard_of.erase(it);
  }
  if (!shard_of.empty())
    throw InputError(plan_path + ": points: " + shard_of.begin()->first +
                     " is not a point of the spec (the spec changed after the plan was made)");
  return selected;
}

}  // namespace aoeval

namespace aoeval {

std::vector<size_t> shard_indices(const std::vector<std::string>& names, const std::string& shard,
                                  const std::string& plan_path) {
  std::vector<size_t> all;
  if (shard.empty()) {
    if (!plan_path.empty()) throw InputError("--shard-plan: needs --shard I/N or --shard auto");
    for (size_t i = 0; i < names.size(); ++i) all.push_back(i);
    return all;
  }
  const auto [index, count] = parse_shard(shard);
  if (!plan_path.empty())
    return planned_shard(read_shard_plan(plan_path), names, index, count, plan_path);
  for (size_t i = static_cast<size_t>(index); i < names.size(); i += static_cast<size_t>(count))
    all.push_back(i);
  return all;
}

}  // namespace aoeval
