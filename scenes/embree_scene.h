// Embree scene building, in one place for the G-buffer, the reference and object-space
// estimators. One triangle geometry per plain scene object and one Embree instance per placement
// of an instanced object; the top-level geomID (instID[0] for an instance hit) is the G-buffer's
// object id (scenes/instances.h PlacementIds; = object index in a scene without instances).
#pragma once

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <atomic>
#include <cstddef>
#include <vector>

#include "scenes/scene.h"

namespace aoeval {

// Makes `context` run its tasks with flush-to-zero and denormals-are-zero on. The calling
// thread's own settings are left as they were.
void capture_ftz_daz(tbb::task_group_context& context);

// tbb::parallel_for(range, body) with flush-to-zero and denormals-are-zero on in every task, on
// every thread, as Embree's documentation asks of every thread that traces rays. Setting the flags
// on a thread is not enough: oneTBB runs each task under the floating-point settings of its
// task_group_context, and the default context takes them once, from the thread that first used
// TBB; scheduler observers' flags are overwritten too. So every loop that traces goes through this.
template <typename Range, typename Body>
void parallel_for_embree(const Range& range, const Body& body) {
  tbb::task_group_context context;
  capture_ftz_daz(context);
  tbb::parallel_for(range, body, context);
}

// The process-wide Embree device; errors are turned into exceptions.
RTCDevice embree_device();
// Bytes Embree has allocated, as reported by its memory monitor.
long long embree_allocated_bytes();

// The G-buffer object id of a hit: the instance's top-level ID, or the plain geometry's.
inline unsigned hit_placement(const RTCHit& hit) {
  return hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? hit.instID[0] : hit.geomID;
}

enum class BuildQuality { low, medium, high };

class EmbreeScene {
 public:
  explicit EmbreeScene(const Scene& scene, BuildQuality quality = BuildQuality::high);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }
  const Scene& scene() const { return source_; }
  double build_ms() const { return build_ms_; }
  long long memory_bytes() const { return memory_bytes_; }  // Embree's share: buffers + BVH

 private:
  const Scene& source_;
  RTCScene scene_ = nullptr;
  std::vector<RTCScene> prototypes_;  // one per instanced object
  double build_ms_ = 0.0;
  long long memory_bytes_ = 0;
};

}  // namespace aoeval
