#include "harness/figures/figure_timing.h"

#include <chrono>

#include "base/mann_whitney.h"
#include "base/summary.h"
#include "estimators/registry.h"

namespace aoeval::figures {

double InterleavedTimes::median(size_t i) const {
  return aoeval::median(ms.at(i));
}

InterleavedTimes time_interleaved(FigureContext& ctx, const std::vector<Contender>& contenders,
                                  int warmup, int rounds) {
  using clock = std::chrono::steady_clock;
  struct Prepared {
    std::unique_ptr<Estimator> estimator;
    const Scene* scene = nullptr;
    const EmbreeScene* embree = nullptr;
    const GBuffer* gbuffer = nullptr;
  };
  std::vector<Prepared> p;
  InterleavedTimes t;
  for (const Contender& c : contenders) {
    const EstimatorInfo& e = find_estimator(c.estimator);
    const ParamSet params = resolve_params(e.name, e.params, c.overrides, "figure " + e.name);
    const auto& data = ctx.session->scene(c.scene);
    Prepared q;
    q.scene = &data.scene;
    q.embree = data.embree.get();
    q.gbuffer = &ctx.session->gbuffer(c.scene, data.scene.view(c.view), c.width, c.height);
    q.estimator = e.create(params);
    q.estimator->prepare({*q.scene, *q.embree, *q.gbuffer});
    t.pixels.push_back(q.gbuffer->pixel_count());
    p.push_back(std::move(q));
  }
  t.ms.assign(p.size(), {});
  t.pass_ms.assign(p.size(), {});
  const size_t n = p.size();
  for (int r = 0; r < warmup + rounds; ++r)
    for (size_t i = 0; i < n; ++i) {
      Prepared& q = p[(static_cast<size_t>(r) + i) % n];
      const EstimateContext in{*q.scene, *q.embree, *q.gbuffer};
      const auto t0 = clock::now();
      const EstimateResult res = q.estimator->run(in);
      const double wall = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
      if (r < warmup) continue;
      const size_t which = (static_cast<size_t>(r) + i) % n;
      const auto total = res.pass_ms.find("total_ms");
      t.ms[which].push_back(total != res.pass_ms.end() ? total->second : wall);
      for (const auto& [pass, ms] : res.pass_ms) t.pass_ms[which][pass].push_back(ms);
    }
  return t;
}

namespace {
std::vector<double> scaled(const std::vector<double>& v, double f) {
  std::vector<double> out(v);
  for (double& x : out) x *= f;
  return out;
}
}  // namespace

double p_slower(const std::vector<double>& a, const std::vector<double>& b, double f) {
  if (a.empty() || b.empty()) return 1.0;
  return mann_whitney(scaled(b, f), a).p_greater;
}

double p_faster(const std::vector<double>& a, const std::vector<double>& b, double f) {
  if (a.empty() || b.empty()) return 1.0;
  return mann_whitney(scaled(b, f), a).p_less;
}

std::string p_text(double p) {
  return "p = " + fmt(p, 2);
}

}  // namespace aoeval::figures
