// The forest's far field, built once and shared (issue 45). A sequence runs a fresh estimator for
// every frame and a sweep one for every point, but the far field (far_field.h's hierarchy and
// far_grid.h's precomputed grid) depends only on the trees' large occluders, the scene's bounds
// and five parameters, never on the camera: a 48-frame fly-through over forest-10k paid the grid's
// 0.4-0.9 s precompute 48 times. A frame whose trees are where the last frame's were now reuses it.
//
// The key is the whole input, compared exactly (every occluder's bytes, not a hash: a collision
// would be a silently wrong image). The last kCapacity fields are kept, most recent first; a trees'
// move (an animated forest) is a different key and builds its own.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "estimators/tree_proxies/far_field.h"
#include "estimators/tree_proxies/far_grid.h"
#include "estimators/tree_proxies/hegeman_model.h"
#include "scenes/mesh.h"

namespace aoeval {

struct FarFields {
  FarField far;  // the hierarchy: pixels outside the grid, and the grid's node sums
  FarGrid grid;  // far_grid_cell > 0 and enough trees: the far part precomputed
};

struct FarFieldsInput {
  std::vector<hegeman::UnitMap> occluders;
  Bounds region;
  double cull = 0.0, angle = 0.0, cell = 0.0, near = 0.0;
  bool horizon = true;
  bool operator==(const FarFieldsInput& other) const;
};

// The fields for `input`, built now or taken from an earlier build of an equal input. Thread-safe;
// a build runs outside the cache's lock (two threads may both build one input; one is kept).
std::shared_ptr<const FarFields> shared_far_fields(const FarFieldsInput& input);

// Builds done by shared_far_fields in this process (what a test of the reuse counts).
size_t far_fields_builds();

}  // namespace aoeval
