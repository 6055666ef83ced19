// The raster G-buffer: the scene's triangles rasterised with the pinhole camera of CONTRACT §3
// (scenes/camera.h: pixel centres at (i + 0.5, j + 0.5), row 0 at the top, vertical fov) into the
// same channels as the Embree G-buffer (scenes/gbuffer.h), kept on the device for the screen-space
// estimators and downloadable as a host GBuffer.
//
// Rasterisation decides visibility only (which triangle covers each pixel centre, reversed-Z
// depth test). The fragment shader then intersects the pixel's camera ray with that triangle and
// computes P, Z, N and Ng exactly as render_gbuffer() does from Embree's hit: barycentric P on the
// triangle's plane, Ng = normalize(cross(p1 - p0, p2 - p0)), N the normalised interpolated vertex
// normal (Ng when the mesh has none), both flipped to face the viewer. So interior pixels agree
// with Embree to float rounding and the two differ only where the rasteriser and Embree's
// watertight test pick different triangles (silhouettes, shared edges, sub-pixel geometry).
#pragma once

#include <vulkan/vulkan.h>

#include <memory>

#include "estimators/vulkan/vk_commands.h"
#include "estimators/vulkan/vk_context.h"
#include "estimators/vulkan/vk_pipelines.h"
#include "estimators/vulkan/vk_resources.h"
#include "scenes/camera.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval::vk {

// The G-buffer on the device: one image per channel, all width x height, in GENERAL layout, usable
// as storage images (and colour attachments). Values as in GBuffer; uncovered pixels hold A = 0,
// Z = 0, P = N = Ng = 0, objectId = -1.
struct DeviceGBuffer {
  int width = 0, height = 0;
  Image2D coverage;          // R32F, A
  Image2D depth;             // R32F, Z: linear view depth along the camera's forward axis
  Image2D position;          // RGBA32F, P.xyz world position, w = A
  Image2D normal;            // RGBA32F, N.xyz unit shading normal facing the viewer, w = 0
  Image2D geometric_normal;  // RGBA32F, Ng.xyz unit geometric normal facing the viewer, w = 0
  Image2D object_id;         // R32F, index into Scene::objects, -1 where A = 0
};

// Allocates the images (zeroed).
DeviceGBuffer make_device_gbuffer(Context& context, int width, int height);
// Uploads a host G-buffer (e.g. the shared Embree one, for gbuffer=embree) into device images.
DeviceGBuffer upload_gbuffer(Context& context, const GBuffer& g);
// Downloads the device images into a host GBuffer with `camera` attached.
GBuffer download_gbuffer(const DeviceGBuffer& d, const Camera& camera);

class RasterGBuffer {
 public:
  // Uploads the scene's triangles (all objects, world space) once.
  RasterGBuffer(Context& context, const Scene& scene);
  ~RasterGBuffer();
  RasterGBuffer(const RasterGBuffer&) = delete;
  RasterGBuffer& operator=(const RasterGBuffer&) = delete;

  // Records the raster pass into `target` (its size must be camera.width x camera.height), timed as
  // pass "geometry" when `timer` is given, followed by a pass_barrier so later passes may read it.
  void record(VkCommandBuffer cmd, const Camera& camera, DeviceGBuffer& target,
              PassTimer* timer = nullptr);
  // Convenience: allocate, record, submit, wait, download.
  GBuffer render(const Camera& camera);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aoeval::vk
