// The reference stage of a --slurm submission (CONTRACT §9): every distinct reference the points
// need (the matched definition of each point and the unbounded cosine "true AO", per scene view
// and resolution and reference settings) is computed once into the shared cache before any
// estimator shard starts, itself split over a job array when there are many. The shards then only
// read the cache; should one still miss (a cache wiped in between), the cache's entry lock
// (references/cache_lock.h) keeps it to one computation.
#pragma once

#include <string>
#include <vector>

#include "harness/sweep/sweep_spec.h"

namespace aoeval {

struct StagePoint {
  const SweepPoint* point = nullptr;
  const SweepSpec* spec = nullptr;  // its reference settings apply
};

struct ReferenceNeed {
  std::string key;  // scene|view|WxH|definition|reference settings
  const SweepPoint* point = nullptr;
  const SweepSpec* spec = nullptr;
  AoDefinition definition;
};

// In order of first need.
std::vector<ReferenceNeed> distinct_references(const std::vector<StagePoint>& points);

// Computes (or finds in the cache) the needs that `shard` (I/N, auto, "" = all) takes: every N-th
// from I. Prints one line per reference on stderr.
void run_reference_stage(const std::vector<StagePoint>& points, const std::string& shard);

}  // namespace aoeval
