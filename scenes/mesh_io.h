// Mesh files: OFF through our own strict reader (the scanned meshes of CONTRACT §6 are OFF, and a
// strict reader can name the line of a malformed file), everything else through assimp.
#pragma once

#include <string>

#include "scenes/mesh.h"

namespace aoeval {

// Loads a triangle mesh (polygons are fan-triangulated). Shading normals come from the file when it
// has them, else they are computed area-weighted. Throws InputError naming `path` on any problem
// (missing file, parse error, no triangles, NaN coordinates, bad indices).
TriangleMesh load_mesh(const std::string& path);

// The OFF reader alone (exposed for tests).
TriangleMesh load_off(const std::string& path);

}  // namespace aoeval
