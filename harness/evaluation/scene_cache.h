// What the runs of a session share before any reference: scenes with their Embree scenes, the
// posed scenes of sequence frames, cameras and G-buffers. Thread-safe (the runner's thread and the
// background lane read it at once); entries never move or vanish.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "harness/results/stage_times.h"
#include "scenes/gbuffer.h"
#include "scenes/sequence_frame.h"

namespace aoeval {

struct SceneData {
  Scene scene;
  std::unique_ptr<EmbreeScene> embree;
  uint64_t content_hash = 0;  // scene.content_hash(), computed once at load
};

class SceneCache {
 public:
  // `stages` receives "scene load + BVH" and "G-buffer".
  explicit SceneCache(StageTimes& stages) : stages_(stages) {}

  const SceneData& scene(const std::string& name);
  // Frame k of a view: the scene posed for it (the scene itself when no object moves), cached.
  const SceneData& frame_scene(const std::string& name, const View& view, int frame);
  // A frame's posed scene that is not kept: a sequence poses its frames one at a time, so that a
  // long sequence holds two frames' geometry at most. (Never moved: its EmbreeScene refers to it.)
  std::unique_ptr<SceneData> posed(const SceneData& base, const SequenceFrame& frame);
  // Frame k's camera (jitter included).
  Camera frame_camera_of(const std::string& name, const View& view, int frame, int w, int h);
  // The first frame of the run of unchanged frames that ends at `frame` (issue 42): its reference
  // is frame k's, traced once. `frame` itself for a still view.
  int reference_frame(const std::string& name, const View& view, int frame);
  // Where one image stands for a view (gbuffer(), reference(), mosaics, the gallery), a sequence
  // view is its last frame: the state a screenshot after the sequence shows.
  static int still_frame(const View& view) { return view.frame_count() - 1; }
  // The G-buffer of the view's still_frame() at a size, cached.
  const GBuffer& gbuffer(const std::string& scene, const View& view, int width, int height);

 private:
  StageTimes& stages_;
  std::recursive_mutex mutex_;
  std::map<std::string, SceneData> scenes_;
  std::map<std::string, GBuffer> gbuffers_;
};

// "scene|view|WxH": the key of a view at a size in the session's caches.
std::string view_key(const std::string& scene, const View& view, int w, int h);

}  // namespace aoeval
