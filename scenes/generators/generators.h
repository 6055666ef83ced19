// Procedural geometry generators, referenced from scene files as
//   {"name": "crown", "generator": "tree", "seed": 7, "params": {...}}
// Every generator is deterministic: the same (seed, params) gives a bit-identical mesh on every
// platform (it draws only from aoeval::SplitMix64 and uses no std:: distributions).
// Every generator reads its parameters through the JsonReader it is given, with defaults and ranges
// inline; the caller calls finish(), so an unknown parameter is an error.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/json_reader.h"
#include "scenes/mesh.h"

namespace aoeval {

struct GeneratedGeometry {
  TriangleMesh mesh;
  // Facts the generator knows exactly and later stages may use, e.g. for trees
  // {"leaf_area": m2, "leaf_count": n, "crown": {"center": [..], "radii": [..]}}, for grass
  // {"blade_height": h}. Written into `aoeval scenes show`.
  nlohmann::json facts = nlohmann::json::object();
};

using GeneratorFunction = GeneratedGeometry (*)(uint64_t seed, JsonReader& params);

struct GeneratorInfo {
  const char* name;
  const char* description;
  GeneratorFunction function;
};

// All generators, in a fixed order.
const std::vector<GeneratorInfo>& generator_registry();
// nullptr when unknown.
const GeneratorInfo* find_generator(const std::string& name);

// The generators themselves (one file each under scenes/generators/).
GeneratedGeometry generate_sphere_uniform(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_tree(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_grass(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_plane(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_terrain(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_box(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_disk(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_sphere(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_cylinder(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_fence(uint64_t seed, JsonReader& params);
GeneratedGeometry generate_chair(uint64_t seed, JsonReader& params);

}  // namespace aoeval
