// Embree scene building, in one place for the G-buffer, the reference and object-space
// estimators. One triangle geometry per scene object, geomID = object index.
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstddef>

#include "scene.h"

namespace aoeval {

// Turns on flush-to-zero and denormals-are-zero (as Embree's documentation asks for performance)
// on the calling thread and, through a TBB observer, on every TBB worker thread. Idempotent.
void enable_ftz_daz_everywhere();

// The process-wide Embree device; errors are turned into exceptions.
RTCDevice embree_device();
// Bytes Embree has allocated, as reported by its memory monitor.
long long embree_allocated_bytes();

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
  double build_ms_ = 0.0;
  long long memory_bytes_ = 0;
};

}  // namespace aoeval
