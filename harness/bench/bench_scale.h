// `aoeval bench scale` (issue 45): how cost grows with the number of trees. The base scene's
// instanced objects (default forest-1k's four tree prototypes) are placed N = 10, 100, 1000,
// 10000 times at the base's density (the placer's square and the ground grow as sqrt(N)); for
// each N: BVH build time, memory (RSS growth and Embree's own), G-buffer time, reference Mrays/s,
// each tree estimator's ms and its rmse against the reference (uniform, unbounded: the definition
// they estimate), raytraced at a few rays beside them, and the same N as copies where copies fit.
// The tree estimators run at `cull` (a radius only) and at each far-field angle `far`
// (far_field.h). With `cached_references` the references come from the reference cache
// (reference_cache.h) and go into it, and a served reference has no Mrays/s.
// Writes bench_scale.json, bench_scale.md (table and log-log slopes) and bench_scale.png.
#pragma once

#include <string>
#include <vector>

namespace aoeval {

struct ScaleBenchOptions {
  std::string base = "forest-1k";
  std::vector<int> counts = {10, 100, 1000, 10000};
  std::string res = "80x60";
  int spp = 64;
  int repetitions = 3;
  int copies_max = 100;             // copies are built for N up to this (and only when they fit)
  double cull = 1e-2;               // cull_occlusion of the culled tree-estimator rows
  bool cached_references = false;   // serve references from the cache (no Mrays/s then)
  std::vector<double> far = {0.7};  // far_field_angle of the far-field rows (one row per angle)
  std::string out_dir = "out/bench-scale";
};

void bench_scale(const ScaleBenchOptions& options);

}  // namespace aoeval
