// A scene as another renderer sees it (`aoeval scenes export`): the world-space triangles the
// reference traces, every instance placed, as one binary PLY, and a view's pinhole camera (the
// basis and field of view of scenes/camera.h) as JSON. tools/cycles_ao_compare.py renders them with
// Blender Cycles to check the reference against an independent ray tracer.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "scenes/camera.h"
#include "scenes/scene.h"

namespace aoeval {

// Every object's triangles in world space (an instanced object once per placement, its prototype
// transformed by the instance matrix), as binary little-endian PLY: element vertex (float x y z),
// element face (list uchar uint vertex_indices), counter-clockwise = front as in TriangleMesh. No
// normals: a renderer reading it shades with geometric normals (the reference's --normal
// geometric; a mesh with its own smooth normals is then compared on that definition). Atomic.
void write_scene_ply(const Scene& scene, const std::string& path);

// The camera of `view` at the given resolution (0: the view's): eye, the unit forward, right and up
// vectors, fov_y_deg, tan_half_fov_y, width, height, and the pixel convention (centre (i + 0.5,
// j + 0.5), row 0 at the top; right-handed, +Y up).
nlohmann::json camera_to_json(const Scene& scene, const View& view, const Camera& camera);

}  // namespace aoeval
