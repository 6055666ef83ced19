// Tree envelopes ("proxies") for the Hegeman et al. 2006 estimators and Reeves-Blau: taken from the
// scene file (SceneObject::proxy) when it has one of the wanted kind, otherwise derived from the
// tree's leaves, and the leaf statistics behind the derived alpha rho (their §3).
//
// Leaves. A tree object's leaves are its triangles after facts.wood_triangles (the tree generator
// stores the wood first); an object without that fact (sphere-uniform, a loaded mesh) is all
// leaves. Everything is computed from the world-space mesh: generator facts are in the generator's
// own space (scene.cpp does not transform them), so they would be wrong for a scaled tree.
//
// Derived proxies (deterministic: serial, in double, fixed seed):
//   sphere     centre = the leaf vertices' bounding-box centre, radius = the largest distance to a
//              leaf vertex (every leaf inside). This is §3's "simple spherical bounding box
//              computation", and the same sphere the tree generator reports as
//              facts.bounding_sphere.
//   ellipsoid  axis-aligned (trees stand upright): centre = the same box centre; semi-axes
//              proportional to the area-weighted RMS deviations of the leaf-triangle centroids from
//              it along x, y, z, scaled by the smallest factor that puts a fraction `coverage`
//              (default 1: all) of the leaf vertices inside. For leaves filling an ellipsoid evenly
//              the RMS deviations are radii / sqrt(5), so the shape is recovered.
//   shells     §5: k-means (Lloyd) on the area-weighted leaf-triangle centroids, k-means++ seeding
//              from SplitMix64(seed); each shell is centred on its cluster's mean and just encloses
//              every vertex of the cluster's triangles, so the shells together cover every leaf.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenes/scene.h"

namespace aoeval {

enum class ProxyKind { sphere, ellipsoid, shells };
const char* proxy_kind_name(ProxyKind kind);

struct ProxyOptions {
  ProxyKind kind = ProxyKind::sphere;
  int shells = 4;         // shells: the k of k-means
  double coverage = 1.0;  // ellipsoid: fraction of leaf vertices inside, in (0, 1]
  uint64_t seed = 1;      // shells: k-means++ seeding
};

// G of §3's Poisson argument: the mean projected area of a randomly oriented flat leaf is 1/2 of
// its one-sided area (the mean of |cos| over the sphere).
constexpr double kLeafProjection = 0.5;

// The leaf triangles of a tree object (see above). InputError naming the object when it has none.
struct LeafSet {
  size_t first_triangle = 0;  // leaves are triangles [first_triangle, triangle_count)
  size_t triangles = 0;
  int64_t count = 0;  // leaves (facts.leaf_count when present, else triangles)
  double area = 0.0;  // one-sided, world space
};
LeafSet tree_leaves(const SceneObject& object);

TreeProxy derive_proxy(const SceneObject& object, const ProxyOptions& options);

// Weighted k-means (Lloyd) with k-means++ seeding; deterministic. `assignment[i]` is point i's
// cluster; every cluster is non-empty when there are at least k distinct points.
struct KMeans {
  std::vector<glm::dvec3> centers;
  std::vector<int> assignment;
  int iterations = 0;
};
KMeans kmeans(const std::vector<glm::dvec3>& points, const std::vector<double>& weights, int k,
              uint64_t seed, int max_iterations = 100);

// What an estimator uses for one tree object.
struct TreeEnvelope {
  size_t object = 0;     // index into Scene::objects
  size_t placement = 0;  // the G-buffer's object id (scenes/instances.h PlacementIds)
  TreeProxy proxy;       // world space
  bool from_scene = false;
  LeafSet leaves;
  // Per shape: lambda = mean number of leaves a ray meets per unit length inside it (§3):
  // G * rho * (leaf area / leaf count) with the scene's density rho when given, else
  // G * (area of the leaf triangles whose centroid is inside the shape) / (shape volume): for
  // overlapping shells that is the local density, whichever cluster the leaves came from.
  std::vector<double> lambda;
};

// One envelope per tree placement, in G-buffer id order. `prefer_scene`: use the scene's proxy when
// it has one of the wanted kind (a sphere also serves as an ellipsoid); otherwise derive it. An
// instanced tree's envelope is derived once from the prototype and placed per instance (issue 45):
// shapes by the instance's transform; with s = cbrt|det| its mean scale, the leaf area by s^2 and
// lambda by 1/s (leaf area over volume) or by s^2 (a scene density times the larger leaf).
// `prototypes`, when given, receives each instanced object's envelope before placement (object
// space, the prototype's leaves), one per object, in object order.
std::vector<TreeEnvelope> tree_envelopes(const Scene& scene, const ProxyOptions& options,
                                         bool prefer_scene,
                                         std::vector<TreeEnvelope>* prototypes = nullptr);

// For records and logs: {"object", "source", "type", "shapes": [{"center", "radii"}], "lambda",
// "leaf_area", "leaf_count"}. The harness should store this beside each result of a tree estimator.
nlohmann::json envelope_to_json(const Scene& scene, const TreeEnvelope& envelope);

}  // namespace aoeval
