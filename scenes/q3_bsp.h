// Quake 3 levels (issue 44): the triangles of an IBSP version 46 map (.bsp), as OpenArena ships
// them inside its .pk3 archives (tools/bootstrap.sh extracts the corpus's maps). Read here because
// Debian 12's assimp 5.2.5 Q3BSP importer fails its own validation on every OpenArena map
// ("aiMesh::mFaces[0]::mIndices[0] is out of range").
//
// What is read: polygon and mesh faces (their mesh vertices), and Bezier patches tessellated
// into 8 x 8 quads per 3 x 3 control block; billboards, and faces whose shader is sky or nodraw,
// are left out (they are not surfaces a player sees). Coordinates are the file's (Z up, one unit
// an inch): the scene file turns and scales them. Each triangle is wound so that its geometric
// normal agrees with the file's vertex normals.
#pragma once

#include <string>

#include "scenes/mesh.h"

namespace aoeval {

// Throws InputError naming `path` (and the lump or face) on a malformed file.
TriangleMesh load_q3_bsp(const std::string& path);

}  // namespace aoeval
