// The shared G-buffer: primary rays through pixel centres (CONTRACT §3), traced with Embree. The
// reference and every estimator read this one buffer, so they all see the same surface points.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "base/coverage.h"
#include "scenes/camera.h"
#include "scenes/embree_scene.h"
#include "scenes/exr_io.h"

namespace aoeval {

struct GBuffer {
  int width = 0;
  int height = 0;
  Camera camera;
  std::vector<float> coverage;      // A: 1 = surface, 0 = background
  std::vector<float> depth;         // Z: linear view depth (along the view axis); 0 if A = 0
  std::vector<glm::vec3> position;  // P: world position
  std::vector<glm::vec3> normal;    // N: unit shading normal, on the viewer's side
  std::vector<glm::vec3> geometric_normal;  // Ng: unit geometric normal, facing the viewer
  std::vector<float> object_id;             // index into Scene::objects; -1 if A = 0
  // Sequence frames only (CONTRACT §10, sequence_frame.h's add_motion), empty otherwise: the offset
  // in pixels from where the pixel's surface point was in frame k - 1 to where it is now, and 1
  // where that point was not visible in frame k - 1.
  std::vector<glm::vec2> motion;
  std::vector<float> disoccluded;

  size_t index(int i, int j) const { return static_cast<size_t>(j) * width + i; }
  bool covered(size_t k) const { return is_covered(coverage[k]); }
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
};

// Traces one primary ray per pixel centre. Two-sided surfaces: Ng is flipped to face the viewer and
// N is flipped with it (so N stays on the same side of the surface as Ng; an interpolated N that
// still points away from the viewer at a silhouette is kept as the mesh gives it).
GBuffer render_gbuffer(const EmbreeScene& scene, const Camera& camera);

// Channel names of CONTRACT §4, in file order (a sequence frame adds motion.X, motion.Y and
// disoccluded after them).
const std::vector<std::string>& gbuffer_channel_names();

OIIO::ImageBuf gbuffer_to_image(const GBuffer& g);
// Reads a G-buffer EXR written by gbuffer_to_image (camera from its aoeval:camera attribute),
// checked by check_gbuffer_values.
GBuffer read_gbuffer(const std::string& path);
// The values check every G-buffer reader applies (read from `path`, named in the message): on
// covered pixels, motion.X/Y and disoccluded are finite. A NaN offset read a previous frame at an
// undefined index (a crash in the temporal scorer), an infinite one passed as "off screen":
// damaged input either way. InputError naming the file, the channel and the pixel.
void check_gbuffer_values(const GBuffer& g, const std::string& path);

// The aoeval:* header attributes of a G-buffer file: scene, view, camera (JSON), version.
Attributes gbuffer_attributes(const Scene& scene, const View& view, const Camera& camera);
// The same with the scene's content_hash() computed once by the caller: hashing a mesh reads
// every byte of it (tens of milliseconds for dragon), and a run writes many files per scene.
Attributes gbuffer_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                              const Camera& camera);
std::string camera_to_json(const Camera& camera);

}  // namespace aoeval
