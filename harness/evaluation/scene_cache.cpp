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

std::shared_ptr<const PosedFrame> SceneCache::posed_frame(const std::string& name, const View& view,
                                                          int k, int w, int h,
                                                          const PosedFrame* prev) {
  const std::string key = view_key(name, view, w, h);
  const SceneData* base = nullptr;
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    auto it = frames_.find(key);
    if (it != frames_.end()) {
      it->second.used = ++frame_tick_;
      const auto found = it->second.frames.find(k);
      if (found != it->second.frames.end()) return found->second;
    }
    base = &scene(name);
  }
  // Built without the lock (only the runner's thread builds frames; the lane reads gbuffer()).
  auto built = std::make_shared<PosedFrame>();
  built->frame = sequence_frame(base->scene, view, k);
  if (built->frame.moves_objects) {
    const auto timer = stages_.time("scene load + BVH");
    auto posed = std::make_shared<SceneData>();
    build(*posed, posed_scene(base->scene, built->frame));
    // Embree's buffers and BVH, and about 64 bytes a triangle for the scene's own arrays.
    built->bytes +=
        static_cast<size_t>(posed->embree->memory_bytes()) + posed->scene.triangle_count() * 64;
    built->posed = std::move(posed);
  }
  built->camera = frame_camera(built->frame, w, h);
  {
    const auto timer = stages_.time("G-buffer");
    auto g = std::make_shared<GBuffer>(
        render_gbuffer(built->posed ? *built->posed->embree : *base->embree, built->camera));
    add_motion(*g, prev ? prev->gbuffer.get() : nullptr, built->frame.motion,
               prev ? prev->frame.motion : built->frame.motion);
    built->bytes += g->pixel_count() * sizeof(float) * 15;  // A, Z, P, N, Ng, id, motion, disocc.
    built->gbuffer = std::move(g);
  }
  std::shared_ptr<const PosedFrame> frame = std::move(built);
  keep_frame(key, k, frame);
  return frame;
}

void SceneCache::keep_frame(const std::string& key, int k,
                            std::shared_ptr<const PosedFrame> frame) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  // Other views' frames out, least recently used first, until this one fits.
  while (frame_bytes_ + frame->bytes > kFrameBytes) {
    auto oldest = frames_.end();
    for (auto it = frames_.begin(); it != frames_.end(); ++it)
      if (it->first != key && (oldest == frames_.end() || it->second.used < oldest->second.used))
        oldest = it;
    if (oldest == frames_.end()) return;  // only this view's frames are kept: not kept
    for (const auto& [index, kept] : oldest->second.frames) frame_bytes_ -= kept->bytes;
    frames_.erase(oldest);
  }
  ViewFrames& view = frames_[key];
  view.used = ++frame_tick_;
  frame_bytes_ += frame->bytes;
  view.frames[k] = std::move(frame);
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
