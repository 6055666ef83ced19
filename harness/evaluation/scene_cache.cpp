#include "harness/evaluation/scene_cache.h"

#include "scenes/corpus.h"

namespace aoeval {

namespace {
// Fills `d` in place: its EmbreeScene refers to d.scene.
void build(SceneData& d, Scene scene) {
  d.scene = std::move(scene);
  d.embree = std::make_unique<EmbreeScene>(d.scene);
  d.content_hash = d.scene.content_hash();
}
}  // namespace

std::string view_key(const std::string& scene, const View& v, int w, int h) {
  return scene + "|" + v.name + "|" + std::to_string(w) + "x" + std::to_string(h);
}

const SceneData& SceneCache::scene(const std::string& name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it = scenes_.find(name);
  if (it != scenes_.end()) return it->second;
  const auto timer = stages_.time("scene load + BVH");
  Scene loaded = load_scene(name);
  SceneData& stored = scenes_[name];
  build(stored, std::move(loaded));
  return stored;
}

std::unique_ptr<SceneData> SceneCache::posed(const SceneData& base, const SequenceFrame& frame) {
  const auto timer = stages_.time("scene load + BVH");
  auto data = std::make_unique<SceneData>();
  build(*data, posed_scene(base.scene, frame));
  return data;
}

const SceneData& SceneCache::frame_scene(const std::string& name, const View& view, int frame) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const SceneData& base = scene(name);
  if (!view.sequence) return base;
  const SequenceFrame f = sequence_frame(base.scene, view, frame);
  if (!f.moves_objects) return base;
  const std::string key = name + "|" + view.name + "|frame " + std::to_string(frame);
  auto it = scenes_.find(key);
  if (it != scenes_.end()) return it->second;
  const auto timer = stages_.time("scene load + BVH");
  SceneData& stored = scenes_[key];
  build(stored, posed_scene(base.scene, f));
  return stored;
}

Camera SceneCache::frame_camera_of(const std::string& name, const View& view, int frame, int w,
                                   int h) {
  return frame_camera(sequence_frame(scene(name).scene, view, frame), w, h);
}

int SceneCache::reference_frame(const std::string& name, const View& view, int frame) {
  if (!view.sequence) return frame;
  return unchanged_since(scene(name).scene, view, frame);
}

const GBuffer& SceneCache::gbuffer(const std::string& scene_name, const View& view, int w, int h) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const std::string key = view_key(scene_name, view, w, h);
  auto it = gbuffers_.find(key);
  if (it != gbuffers_.end()) return it->second;
  const int k = still_frame(view);
  const SceneData& s = frame_scene(scene_name, view, k);
  const Camera camera = frame_camera_of(scene_name, view, k, w, h);
  const auto timer = stages_.time("G-buffer");
  return gbuffers_[key] = render_gbuffer(*s.embree, camera);
}

}  // namespace aoeval
