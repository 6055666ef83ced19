// Instanced objects (issue 45): one prototype mesh placed many times, as Embree 3 holds it
// (RTC_GEOMETRY_TYPE_INSTANCE over a committed prototype scene, one level). The scene file's
// "instances" key (README "Instanced objects") is read here; so are the rules every consumer
// shares: how G-buffer object ids are assigned to placements, the world-space triangle of a
// placement (bit-identical to the object written as copies), the copies themselves, and the
// memory estimates that refuse what would not fit.
#pragma once

#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "base/json_reader.h"
#include "scenes/scene.h"

namespace aoeval {

// Placements beyond this are refused (10^7): each costs Embree an instance geometry and about 88
// bytes of top-level BVH (ospray issue #537), and aoeval 64 bytes of matrix, so 10^7 placements are
// a few GB; 10^8 would not fit any machine here.
inline constexpr size_t kMaxInstances = 10'000'000;
// Memory budgets for the up-front guard (not an accounting; measured peaks stay below them):
// a triangle of an Embree scene built at high quality (index and vertex buffers, BVH with spatial
// splits, aoeval's own mesh copy), and one placement of a prototype.
inline constexpr size_t kBytesPerTriangleBudget = 160;
inline constexpr size_t kBytesPerInstanceBudget = 512;

// The placement matrix of a "transform"-style object: scale, then rotation (X, then Y, then Z,
// degrees), then translation.
glm::mat4 placement_matrix(const glm::vec3& translate, const glm::vec3& rotate_deg,
                           const glm::vec3& scale);

// Reads an object's "instances": an array of {"translate", "rotate_deg", "scale"} or a placer
// object ({"placer": "jittered-grid", ...}, README). `local` is the prototype's bounds (after its
// own fit/transform), used to check that every placed copy stays inside kMaxSceneCoordinate.
// Every error is an InputError naming the file, the field and the instance.
std::vector<glm::mat4> read_instances(JsonReader& object, const Bounds& local);

// Checks one placement: finite entries, an invertible linear part (|det| > 1e-12 of the product of
// its column lengths, and no column shorter than 1e-6) and placed bounds within
// kMaxSceneCoordinate. Throws InputError "<where>: <reason>".
void validate_instance(const glm::mat4& m, const Bounds& local, const std::string& where);

// G-buffer object ids (objectId): placements in file order. A plain object takes one id, an
// instanced object one id per instance, in its list order. A scene without instances keeps ids =
// object index; an instanced scene gets the ids its copies (scene_as_copies) would get.
struct PlacementIds {
  std::vector<size_t> first;  // first id of each object
  size_t count = 0;           // ids in all
  explicit PlacementIds(const Scene& scene);
  size_t object_of(size_t id) const;  // the object placed as `id`; count when out of range
};

// World-space position / shading normal of a prototype vertex under placement `m`: the same float
// operations scene loading applies to a plain object's "transform", so copies and instances agree
// to the bit.
inline glm::vec3 place_point(const glm::mat4& m, const glm::vec3& p) {
  return glm::vec3(m * glm::vec4(p, 1.0f));
}
glm::mat3 placement_normal_matrix(const glm::mat4& m);

// Whether any object is instanced; the number of triangles as placed (every instance counted).
bool has_instances(const Scene& scene);
size_t instanced_triangle_count(const Scene& scene);
size_t instance_count(const Scene& scene);

// Estimated bytes to build the scene for Embree: instanced as it is, or with every instance a copy.
double estimated_bytes(const Scene& scene, bool as_copies);
// InputError "scene 'S': <what> needs about X GiB of memory (...); this machine has Y GiB
// available" when `bytes` exceed `available` (0 = unknown: nothing is refused).
void check_scene_memory(const Scene& scene, double bytes, size_t available,
                        const std::string& what);

// The scene with every instance written out as its own object ("<name>#<i>", same role, albedo,
// density, proxy placed), in placement order, so object index = PlacementIds id. Refused up front
// (check_scene_memory against available_memory_bytes()) when the copies would not fit.
Scene scene_as_copies(const Scene& scene);

// InputError naming the scene, the first instanced object and `consumer` for code that reads
// world-space meshes and does not take instances.
void refuse_instances(const Scene& scene, const std::string& consumer);

}  // namespace aoeval
