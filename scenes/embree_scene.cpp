#include "scenes/embree_scene.h"

#include "base/input_limits.h"
#include "scenes/instances.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <chrono>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>

namespace aoeval {

namespace {

std::atomic<long long> g_embree_bytes{0};

bool memory_monitor(void*, ssize_t bytes, bool) {
  g_embree_bytes += bytes;
  return true;
}

// Embree calls this from C code, so it must not throw: it records the message, and
// check_device() turns it into an exception at a safe point.
std::mutex g_error_mutex;
std::string g_last_error;

void error_handler(void*, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  std::lock_guard<std::mutex> lock(g_error_mutex);
  g_last_error = std::string("Embree error ") + std::to_string(static_cast<int>(code)) + ": " +
                 (message ? message : "");
}

void check_device(RTCDevice device, const char* during) {
  if (rtcGetDeviceError(device) == RTC_ERROR_NONE) return;
  std::lock_guard<std::mutex> lock(g_error_mutex);
  throw std::runtime_error(std::string(during) + ": " + g_last_error);
}

}  // namespace

void capture_ftz_daz(tbb::task_group_context& context) {
  const unsigned caller = _mm_getcsr();
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  context.capture_fp_settings();
  _mm_setcsr(caller);
}

RTCDevice embree_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    if (!d) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(d, error_handler, nullptr);
    rtcSetDeviceMemoryMonitorFunction(d, memory_monitor, nullptr);
    return d;
  }();
  return device;
}

long long embree_allocated_bytes() {
  return g_embree_bytes.load();
}

namespace {

RTCGeometry triangle_geometry(RTCDevice device, const TriangleMesh& mesh, RTCBuildQuality q) {
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geom, q);
  // Embree reads vertex buffers with 16-byte loads, so it owns padded copies.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.positions.size()));
  std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * 3 * sizeof(float));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(unsigned));
  rtcCommitGeometry(geom);
  return geom;
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, BuildQuality quality) : source_(scene) {
  // Refused up front, before Embree allocates: the prototypes' triangles and the placements.
  if (has_instances(scene))
    check_scene_memory(scene, estimated_bytes(scene, false), available_memory_bytes(),
                       "the instanced scene");
  RTCDevice device = embree_device();
  const long long bytes_before = embree_allocated_bytes();
  const auto start = std::chrono::steady_clock::now();
  scene_ = rtcNewScene(device);
  // Robust traversal: watertight edges, so rays through shared edges cannot leak between triangles
  // and bias the reference towards "open".
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  const RTCBuildQuality q = quality == BuildQuality::low      ? RTC_BUILD_QUALITY_LOW
                            : quality == BuildQuality::medium ? RTC_BUILD_QUALITY_MEDIUM
                                                              : RTC_BUILD_QUALITY_HIGH;
  rtcSetSceneBuildQuality(scene_, q);
  // Top-level geometry IDs are the G-buffer's object ids (instances.h PlacementIds): a plain
  // object's triangles, or one RTC_GEOMETRY_TYPE_INSTANCE per placement of an instanced object
  // over its prototype scene (one level of instancing, Embree 3).
  const PlacementIds ids(scene);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& object = scene.objects[i];
    if (object.instances.empty()) {
      RTCGeometry geom = triangle_geometry(device, object.mesh, q);
      rtcAttachGeometryByID(scene_, geom, static_cast<unsigned>(ids.first[i]));
      rtcReleaseGeometry(geom);
      continue;
    }
    RTCScene prototype = rtcNewScene(device);
    prototypes_.push_back(prototype);
    rtcSetSceneFlags(prototype, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(prototype, q);
    RTCGeometry mesh = triangle_geometry(device, object.mesh, q);
    rtcAttachGeometryByID(prototype, mesh, 0);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(prototype);
    for (size_t k = 0; k < object.instances.size(); ++k) {
      RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(inst, prototype);
      rtcSetGeometryTimeStepCount(inst, 1);
      rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                              &object.instances[k][0][0]);
      rtcCommitGeometry(inst);
      rtcAttachGeometryByID(scene_, inst, static_cast<unsigned>(ids.first[i] + k));
      rtcReleaseGeometry(inst);
    }
  }
  rtcCommitScene(scene_);
  check_device(device, "building the Embree scene");
  build_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  memory_bytes_ = embree_allocated_bytes() - bytes_before;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  for (RTCScene p : prototypes_) rtcReleaseScene(p);
}

}  // namespace aoeval
