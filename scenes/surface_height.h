// The height of a mesh seen from above (issue 45): what objects placed "on" a terrain stand on
// (scenes/stand_on.h) and what the grass term measures a blade's height from (tree_scene.h).
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "scenes/mesh.h"

namespace aoeval {

struct SurfacePoint {
  float y = 0.0f;    // the triangle's height at (x, z)
  glm::vec3 normal;  // its unit geometric normal, turned to face +Y
};

class SurfaceHeight {
 public:
  // Indexes the mesh's triangles (world space) by their (x, z) footprints in a uniform grid of
  // about one triangle per cell. Triangles seen edge-on from above (vertical walls) are skipped.
  // With `within`, only the triangles whose footprint meets that rectangle are kept: a query
  // inside it gives the same answer (Terrain.AFootprintsQueryAnswersAsTheWholeSurfaces), and a
  // grass field's prepare indexes its 16 x 16 m, not the whole 430 m terrain, every frame.
  struct Footprint {
    double x0, x1, z0, z1;
  };
  explicit SurfaceHeight(const TriangleMesh& mesh,
                         const std::optional<Footprint>& within = std::nullopt);

  // The highest triangle over (x, z) and its height there, interpolated on the triangle
  // (barycentric weights in double, so a point of the triangle's own plane comes back to within
  // float rounding); nullopt where no triangle covers (x, z). Edges and vertices count as covered.
  std::optional<SurfacePoint> at(double x, double z) const;

 private:
  // A kept triangle: its first vertex, its edges' heights and the rows of the inverse of its
  // (x, z) edge matrix, so that the barycentrics of p are u = (p - a) . ru, v = (p - a) . rv.
  struct Triangle {
    double ax, az, ay, ux, uz, vx, vz, dy1, dy2;
  };
  std::vector<Triangle> triangles_;
  std::vector<glm::vec3> normals_;  // unit, facing +Y
  std::vector<uint32_t> start_, items_;
  double x0_ = 0.0, z0_ = 0.0, cell_x_ = 1.0, cell_z_ = 1.0;
  int nx_ = 1, nz_ = 1;
};

}  // namespace aoeval
