#include "harness/cluster/reference_stage.h"

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

#include "harness/evaluation/evaluation.h"
#include "harness/sweep/shard_plan.h"

namespace aoeval {

std::vector<ReferenceNeed> distinct_references(const std::vector<StagePoint>& points) {
  std::vector<ReferenceNeed> needs;
  std::set<std::string> seen;
  for (const StagePoint& sp : points) {
    const SweepPoint& p = *sp.point;
    const ParamSet params =
        resolve_params(p.estimator->name, p.estimator->params, p.overrides, p.name);
    for (const AoDefinition& d : {p.estimator->definition(params), true_ao_definition()}) {
      const std::string key = p.scene + "|" + p.view + "|" + std::to_string(p.width) + "x" +
                              std::to_string(p.height) + "|" + d.to_json().dump() + "|" +
                              sp.spec->reference.to_json().dump();
      if (seen.insert(key).second) needs.push_back({key, &p, sp.spec, d});
    }
  }
  return needs;
}

void run_reference_stage(const std::vector<StagePoint>& points, const std::string& shard) {
  const std::vector<ReferenceNeed> needs = distinct_references(points);
  std::vector<std::string> keys;
  for (const auto& n : needs) keys.push_back(n.key);
  std::map<std::string, std::unique_ptr<EvaluationSession>> sessions;
  const std::vector<size_t> mine = shard_indices(keys, shard, "");
  std::fprintf(stderr, "references: %zu distinct, %zu in this task\n", needs.size(), mine.size());
  for (size_t i : mine) {
    const ReferenceNeed& n = needs[i];
    auto& session = sessions[n.spec->reference.to_json().dump()];
    if (!session) session = std::make_unique<EvaluationSession>(n.spec->reference, n.spec->timing);
    const auto t0 = std::chrono::steady_clock::now();
    const View& view = session->scene(n.point->scene).scene.view(n.point->view);
    session->reference(n.point->scene, view, n.point->width, n.point->height, n.definition);
    std::fprintf(stderr, "references: %s (%.1f s)\n", n.key.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
}

}  // namespace aoeval
