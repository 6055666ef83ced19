// Objects that stand on another (issue 45, README "Instanced objects", key "on"): after every
// object of a scene file is loaded, an instanced object's placements are lifted by the height of
// the named object's surface at their (x, z), and a grass field's blades each by the height at
// their root, so trunks and blades meet the terrain's triangles exactly (scenes/surface_height.h).
#pragma once

#include <optional>

#include "scenes/scene.h"

namespace aoeval {

// Lifts every object with a non-empty `on` onto the named object (which must exist, be neither
// instanced nor standing on another itself, and cover every spot from above). A placement's
// translation y gains the height at its translation's (x, z); a grass blade (2 segments + 1
// vertices, as the grass generator lays them out) moves up rigidly by the height at the midpoint
// of its two root vertices. Placements are validated again once lifted. Throws one InputError
// naming the scene file, the object and the first spot that fails.
void stand_on_surfaces(Scene& scene);

// A grass field's blade height as laid out by the grass generator: the largest rise from a blade's
// root midpoint to its tip (exact for blades lifted rigidly); nullopt without the generator's
// facts.
std::optional<float> grass_blade_height(const SceneObject& grass);

}  // namespace aoeval
