// `aoeval bench reference`: how close the reference comes to the machine's Embree limit, and how
// much accuracy each sampler buys at equal rays.
#pragma once

#include <string>

#include "references/reference.h"

namespace aoeval {

struct ReferenceBenchOptions {
  std::string scene, view, res;
  int spp = ReferenceSettings{}.spp;
  int repetitions = 5;
  std::string accuracy_res = "96x72";  // resolution of the sampler-accuracy part
  int truth_spp = 16384;
  bool skip_accuracy = false;
};

void bench_reference(const ReferenceBenchOptions& options);

}  // namespace aoeval
