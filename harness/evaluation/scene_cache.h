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

// One sequence frame, posed and rendered (SceneCache::posed_frame()).
struct PosedFrame {
  SequenceFrame frame;
  std::shared_ptr<const SceneData> posed;  // null when no object moves: the scene itself
  Camera camera;                           // jitter included
  std::shared_ptr<const GBuffer> gbuffer;  // motion and disocclusion included
  size_t bytes = 0;                        // what keeping it costs, about
};

class SceneCache {
 public:
  // `stages` receives "scene load + BVH" and "G-buffer".
  explicit SceneCache(StageTimes& stages) : stages_(stages) {}

  const SceneData& scene(const std::string& name);
  // Frame k of a view: the scene posed for it (the scene itself when no object moves), cached.
  const SceneData& frame_scene(const std::string& name, const View& view, int frame);
  // Frame k of a sequence view at a size as run_frames() runs it (posed scene, camera, G-buffer
  // with motion and disocclusion from `prev`, frame k - 1's, null for frame 0), built once for
  // every point of the view (issue 42: 28 sequence points over 5 views rendered about 950
  // G-buffers for about 170 distinct frames). Kept up to kFrameBytes, the least recently used
  // view's frames dropped first; a frame that does not fit is built again for the next point.
  std::shared_ptr<const PosedFrame> posed_frame(const std::string& scene, const View& view, int k,
                                                int w, int h, const PosedFrame* prev);
  static constexpr size_t kFrameBytes = size_t{512} << 20;
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
  // posed_frame()'s frames by view_key() and frame, and when each view was last used.
  struct ViewFrames {
    std::map<int, std::shared_ptr<const PosedFrame>> frames;
    uint64_t used = 0;
  };
  std::map<std::string, ViewFrames> frames_;
  size_t frame_bytes_ = 0;
  uint64_t frame_tick_ = 0;
  void keep_frame(const std::string& key, int k, std::shared_ptr<const PosedFrame> frame);
};

// "scene|view|WxH": the key of a view at a size in the session's caches.
std::string view_key(const std::string& scene, const View& view, int w, int h);

}  // namespace aoeval
