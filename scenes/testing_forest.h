// A small instanced forest for tests (issue 45): a ground plane, two small tree prototypes placed
// by the jittered-grid placer (shares 0 and 1 of 12 cells), and a sphere placed by an explicit list
// that includes a mirroring, a non-uniform scale and a rotation about all three axes. With
// `terrain`, the ground is a sloping noise terrain and the trees and rocks stand "on" it. Written
// to `dir`/forest.json; returns its path.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace aoeval::testutil {

inline std::string write_small_forest(const std::filesystem::path& dir, bool terrain = false) {
  const std::string tree_params =
      R"("params": {"style": "apple", "height": 2.0, "crown_height": 1.4, "crown_radius": 0.8,
                    "branches": 3, "sub_branches": 2, "depth": 3, "leaves_per_twig": 6,
                    "leaf_size": 0.12, "sides": 5})";
  const std::string placer = R"("placer": "jittered-grid", "seed": 5, "count": 12,
      "center": [0, 0, 0], "size": [8, 6], "scale": [0.8, 1.25], "rotate_y_deg": [0, 360])";
  const std::string ground =
      terrain ? R"("generator": "terrain", "seed": 9, "params": {"size": [12, 12], "resolution": 24,
                   "amplitude": 0.4, "feature_length": 6, "octaves": 2, "slope": [0.1, 0.05]})"
              : R"("generator": "plane", "params": {"size": [12, 12]})";
  const std::string on = terrain ? R"("on": "ground", )" : "";
  const std::string text = R"({
  "objects": [
    {"name": "ground", "role": "ground", )" +
                           ground + R"(},
    {"name": "oak", "generator": "tree", "seed": 3, "role": "tree", )" +
                           on + tree_params + R"(,
     "proxy": {"type": "sphere", "center": [0, 1.4, 0], "radius": 0.8}, "density": 2.0,
     "instances": {)" + placer +
                           R"(, "share": [0, 2]}},
    {"name": "birch", "generator": "tree", "seed": 4, "role": "tree", )" +
                           on + tree_params + R"(,
     "instances": {)" + placer +
                           R"(, "share": [1, 2]}},
    {"name": "rock", "generator": "sphere", )" +
                           on + R"("params": {"radius": 0.4, "subdivisions": 2},
     "transform": {"translate": [0, 0.3, 0]},
     "instances": [{"translate": [-1.5, 0, 2.0], "rotate_deg": [10, 35, -20]},
                   {"translate": [1.2, 0, 2.4], "scale": [-1, 1, 1]},
                   {"translate": [0.3, 0, 3.1], "scale": [1.5, 0.6, 1.0], "rotate_deg": [0, 70, 0]}]}
  ],
  "views": [
    {"name": "ground", "eye": [0.3, 1.1, 5.5], "target": [0, 0.9, 0], "fov_y_deg": 60,
     "width": 48, "height": 36},
    {"name": "aerial", "eye": [0.5, 9, 4], "target": [0, 0, 0], "fov_y_deg": 60,
     "width": 48, "height": 36}
  ]
})";
  const std::filesystem::path path = dir / "forest.json";
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace aoeval::testutil
