// The preprocess and the lookup of the vertex-baked estimator (Pharr and Green 2004, GPU Gems
// ch. 17 §17.2, Listing 17-1): accessibility and the average unoccluded direction ("bent normal")
// ray traced at the centre of every triangle, averaged to the vertices, and interpolated
// barycentrically where a pixel's primary ray hits the surface (§17.4, the vertex-shader path).
//
// Two-sided surfaces (CONTRACT §3): every triangle is baked on both sides. Side 0 is the front (the
// side cross(p1 - p0, p2 - p0) points to), side 1 the back; a pixel reads the side its viewer is
// on. Vertices average each side separately, front with front, which assumes consistent winding
// (mesh.h: counter-clockwise = front).
//
// Tessellation: `subdivide` levels each split every triangle into 4 at its edge midpoints (shared
// between neighbours, so vertices stay shared) before baking. Child c of triangle t at level l is
// triangle 4 t + c at level l + 1, so after L levels the sub-triangles of an original triangle p
// are p 4^L ... p 4^L + 4^L - 1, and a hit's (p, u, v) finds its sub-triangle by descent.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "sampling/samplers.h"
#include "scenes/embree_scene.h"
#include "scenes/scene.h"

namespace aoeval {

struct BakeSettings {
  // No defaults here: vertex-baked's parameter table declares them once (vertex_baked.cpp).
  int rays;       // rays per triangle and side (Listing 17-1's "set of rays over the hemisphere")
  int subdivide;  // 1:4 midpoint splits before baking
  SamplerKind sampler;
  uint64_t seed;
};

// One scene object's (subdivided) mesh and its per-vertex values, per side.
struct BakedMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
  // Per vertex and side: the area-weighted mean over incident triangles of their accessibility
  // (unoccluded rays / rays) and of their mean unoccluded direction (sum of unoccluded directions /
  // rays, not normalised, so that averaging stays linear; it is normalised per pixel).
  std::vector<float> accessibility[2];
  std::vector<glm::vec3> bent[2];
};

struct VertexBake {
  int subdivide = 0;
  std::vector<BakedMesh> objects;  // index = Scene::objects index = Embree geomID
  uint64_t rays_traced = 0;
};

// The largest number of triangles a bake may have after subdivision: it holds about 90 bytes per
// sub-triangle at its peak (measured on bunny at subdivide 2), so about 3 GB at this limit.
constexpr uint64_t kMaxBakedTriangles = uint64_t{1} << 25;

// Throws InputError naming `subdivide` when the scene would exceed kMaxBakedTriangles.
void check_subdivide(const Scene& scene, int levels);

// The mesh split `levels` times 1:4 at shared edge midpoints (children of t at 4 t + c, see above).
// Normals are dropped: the bake uses geometric normals.
TriangleMesh subdivide_mesh(const TriangleMesh& mesh, int levels);

// The preprocess: traces 2 * rays * (sub-)triangles occlusion rays with Embree against the
// original scene (the subdivided meshes lie in the same planes). Deterministic: every triangle and
// side draws from its own stream and vertices are summed in a fixed order.
VertexBake bake_vertices(const Scene& scene, const EmbreeScene& embree, const BakeSettings& s);

struct BakedSample {
  float accessibility = 1.0f;
  glm::vec3 bent{0.0f};  // unit, or zero where every ray was occluded
};

// The interpolated values at barycentrics (u, v) (Embree's: P = (1-u-v) p0 + u p1 + v p2) of
// original triangle `prim` of object `geom`, on `side` (0 front, 1 back).
BakedSample lookup(const VertexBake& bake, unsigned geom, unsigned prim, float u, float v,
                   int side);

}  // namespace aoeval
