#include "scenes/generators/generators.h"

namespace aoeval {

const std::vector<GeneratorInfo>& generator_registry() {
  static const std::vector<GeneratorInfo> registry = {
      {"sphere-uniform", "small random triangles uniformly filling a ball (Hegeman et al. Fig. 2)",
       generate_sphere_uniform},
      {"tree", "a tree: trunk, recursive branches and leaves; style apple or poplar",
       generate_tree},
      {"grass", "a field of grass blades of known height (Hegeman et al. eq. 9)", generate_grass},
      {"plane", "a rectangle in the y = 0 plane, facing +Y", generate_plane},
      {"terrain", "a height field of smooth value noise over a rectangle, facing +Y",
       generate_terrain},
      {"box", "an axis-aligned box, optionally facing inward and with open faces", generate_box},
      {"disk", "a disk in the y = 0 plane, facing -Y or +Y", generate_disk},
      {"sphere", "a geodesic sphere", generate_sphere},
      {"cylinder", "a capped cylinder along +Y", generate_cylinder},
      {"fence", "a picket fence of thin boxes on two rails (thin occluders)", generate_fence},
      {"chair", "a chair with thin legs, back posts and slats (thin occluders)", generate_chair},
  };
  return registry;
}

const GeneratorInfo* find_generator(const std::string& name) {
  for (const auto& g : generator_registry())
    if (name == g.name) return &g;
  return nullptr;
}

}  // namespace aoeval
