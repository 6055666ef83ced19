#include "harness/evaluation/reference_store.h"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "harness/evaluation/background_lane.h"
#include "references/cache_lock.h"
#include "references/reference_cache.h"

namespace aoeval {

namespace fs = std::filesystem;

nlohmann::json ReferenceSpec::to_json() const {
  return {{"spp", spp}, {"sampler", sampler_name(sampler)}, {"seed", seed}};
}

ReferenceSettings ReferenceSpec::settings(const AoDefinition& definition) const {
  ReferenceSettings s;
  s.spp = spp;
  s.sampler = sampler;
  s.seed = seed;
  s.definition = definition;
  return s;
}

std::vector<uint8_t> compared_pixels(const GBuffer& g, const ReferenceImage& ref) {
  std::vector<uint8_t> mask(g.pixel_count());
  for (size_t k = 0; k < mask.size(); ++k) mask[k] = g.covered(k) && ref.covered(k);
  return mask;
}

ReferenceSettings ReferenceStore::frame_settings(const std::string& name, const View& view,
                                                 int frame, const AoDefinition& definition) {
  const ReferenceSettings s = spec_.settings(definition);
  return view.sequence ? frame_reference_settings(s, scenes_.reference_frame(name, view, frame))
                       : s;
}

void ReferenceStore::plan(const std::string& scene, const std::string& view, int w, int h,
                          const std::vector<AoDefinition>& definitions) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::vector<AoDefinition>& planned =
      planned_[scene + "|" + view + "|" + std::to_string(w) + "x" + std::to_string(h)];
  for (const AoDefinition& d : definitions)
    if (std::find(planned.begin(), planned.end(), d) == planned.end()) planned.push_back(d);
}

std::vector<AoDefinition> ReferenceStore::planned_definitions(const std::string& name,
                                                              const View& view, int w, int h) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const Scene& base = scenes_.scene(name).scene;
  std::vector<AoDefinition> out;
  // A request names its view and size as the user wrote them: "" is the scene's first view, 0 its
  // own size.
  for (const std::string& v : {view.name, std::string()}) {
    if (v.empty() && (base.views.empty() || base.views.front().name != view.name)) continue;
    for (const std::string& size :
         {std::to_string(w) + "x" + std::to_string(h), std::to_string(w) + "x0",
          "0x" + std::to_string(h), std::string("0x0")}) {
      if (size[0] == '0' && view.width != w) continue;
      if (size.ends_with("x0") && view.height != h) continue;
      const auto it = planned_.find(name + "|" + v + "|" + size);
      if (it == planned_.end()) continue;
      for (const AoDefinition& d : it->second)
        if (std::find(out.begin(), out.end(), d) == out.end()) out.push_back(d);
    }
  }
  return out;
}

void ReferenceStore::compute_missing(const std::string& scene_name, const View& view, int w, int h,
                                     const AoDefinition& definition) {
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    const std::string key = view_key(scene_name, view, w, h) + "|" + definition.to_json().dump();
    if (references_.count(key)) return;
    if (disk_cache_) {
      const int k = SceneCache::still_frame(view);
      const SceneData& s = scenes_.frame_scene(scene_name, view, k);
      const std::string path = reference_cache_path(
          reference_cache_key(s.content_hash, scenes_.frame_camera_of(scene_name, view, k, w, h),
                              frame_settings(scene_name, view, k, definition)));
      if (fs::exists(path)) return;  // read when scored (a damaged entry is recomputed then)
    }
  }
  reference(scene_name, view, w, h, definition);
}

const ReferenceImage& ReferenceStore::reference(const std::string& scene_name, const View& view,
                                                int w, int h, const AoDefinition& definition) {
  const std::string key = view_key(scene_name, view, w, h) + "|" + definition.to_json().dump();
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    auto it = references_.find(key);
    if (it != references_.end()) return it->second;
  }
  // Read or computed without the lock: the background lane reads references while the runner's
  // thread asks whether the next point's are cached, and a lock held through a 15 ms EXR read
  // made the runner wait (issue 16). Only the runner's thread computes (compute_missing, before a
  // point is scored, and the lane scores points whose references exist), so two threads at most
  // read the same file twice; the first copy stored wins.
  const int k = SceneCache::still_frame(view);
  const SceneData& s = scenes_.frame_scene(scene_name, view, k);
  const GBuffer& g = scenes_.gbuffer(scene_name, view, w, h);
  ReferenceImage image =
      reference_image(s, view, g.camera, g, frame_settings(scene_name, view, k, definition),
                      planned_definitions(scene_name, view, w, h));
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  return references_.emplace(key, std::move(image)).first->second;
}

namespace {
// The cache's entries are read by aoeval alone and never kept in a report: zlib at level 1
// instead of OpenEXR's 4 writes a 320x240 reference in 11 ms instead of 14 (two threads) for
// 0.7 % more bytes (measured on a default-suite entry, 879 against 873 KB).
constexpr const char* kCacheCompression = "zip:1";
// A traced reference as its cache entry reads back (reference_to_image without spp, then
// read_reference_image): the same float32 pixels (zip is lossless), spp 0, bent_stderr 0 where it
// was not traced, and no counts. A session keeps what it traced in this form, so a cold run scores
// against exactly what a warm one reads.
ReferenceImage as_read_back(ReferenceImage r) {
  const size_t n = r.ao.size();
  r.spp.assign(n, 0.0f);
  if (r.bent_stderr.empty()) r.bent_stderr.assign(n, 0.0f);
  r.rays_traced = 0;
  r.samples = 0;
  r.seconds = 0.0;
  return r;
}
}  // namespace

ReferenceImage ReferenceStore::trace_references(const SceneData& s, const View& view,
                                                const Camera& camera, const GBuffer& g,
                                                const ReferenceSettings& settings,
                                                const std::vector<AoDefinition>& companions) {
  // The definitions traced with this one: the companions of its weighting whose cache entries do
  // not exist yet (adaptive references trace one definition at a time).
  std::vector<AoDefinition> batch = {settings.definition};
  std::vector<std::string> keys = {reference_cache_key(s.content_hash, camera, settings)};
  if (settings.target_stderr <= 0.0)
    for (const AoDefinition& d : companions) {
      if (d.weighting != settings.definition.weighting ||
          std::find(batch.begin(), batch.end(), d) != batch.end())
        continue;
      ReferenceSettings other = settings;
      other.definition = d;
      const std::string key = reference_cache_key(s.content_hash, camera, other);
      {
        std::lock_guard<std::recursive_mutex> lock(mutex_);
        if (untaken_.count(key) != 0 || pending_.count(key) != 0) continue;
      }
      if (disk_cache_ && fs::exists(reference_cache_path(key))) continue;
      batch.push_back(d);
      keys.push_back(key);
    }
  std::vector<ReferenceImage> traced;
  {
    const auto timer = stages_.time("reference compute");
    traced = compute_references(*s.embree, g, settings, batch);
  }
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    counts_.traces += 1;
    counts_.references += batch.size();
    counts_.rays += traced[0].rays_traced;
  }
  // The companions' entries, and the companions in memory for their one request, as their
  // entries would read back: a cold run does not read what it has just traced (issue 42: 15 s of
  // a 303 s cold default run).
  for (size_t i = 1; i < batch.size(); ++i) {
    if (disk_cache_) {
      ReferenceSettings other = settings;
      other.definition = batch[i];
      write_companion(s, view, camera, other, keys[i], traced[i]);
    }
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    untaken_[keys[i]] = as_read_back(std::move(traced[i]));
  }
  return std::move(traced[0]);
}

void ReferenceStore::write_companion(const SceneData& s, const View& view, const Camera& camera,
                                     const ReferenceSettings& settings, const std::string& key,
                                     ReferenceImage traced) {
  // Each entry complete before it is renamed into place (write_exr is atomic): a shard that traced
  // the same entry meanwhile wrote the same bits. Not under the entry's lock: the runner's thread
  // may hold the lock of the entry it traces, and another shard the companion's.
  auto image = std::make_shared<const ReferenceImage>(std::move(traced));
  Attributes attributes = reference_attributes(s.scene, s.content_hash, view, camera, settings);
  auto write = [this, image, attributes = std::move(attributes), key]() mutable {
    {
      const auto timer = stages_.time("reference write (cache)");
      const std::string path = reference_cache_path(key);
      if (!fs::exists(path)) {
        const OIIO::ImageBuf written = reference_to_image(*image, false);
        add_cache_attributes(attributes, key, written);
        write_exr(path, written, attributes, kCacheCompression);
      }
    }
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    pending_.erase(key);
  };
  std::function<void(std::function<void()>)> writer;
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    if (!BackgroundLane::on_lane_thread()) writer = writer_;
    if (writer) pending_[key] = image;
  }
  if (writer)
    writer(std::move(write));
  else
    write();
}

ReferenceImage ReferenceStore::frame_reference(const SceneData& s, const View& view,
                                               const Camera& camera, const GBuffer& g,
                                               const ReferenceSettings& settings,
                                               const std::vector<AoDefinition>& companions) {
  const std::string key = reference_cache_key(s.content_hash, camera, settings);
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    const auto it = recent_.find(key);
    if (it != recent_.end()) {
      it->second.used = ++recent_tick_;
      return it->second.image;
    }
  }
  ReferenceImage image = reference_image(s, view, camera, g, settings, companions);
  Recent kept;
  kept.image.width = image.width;
  kept.image.height = image.height;
  kept.image.ao = image.ao;
  kept.image.stderr_ao = image.stderr_ao;
  kept.image.coverage = image.coverage;
  const size_t bytes = 3 * image.ao.size() * sizeof(float);
  constexpr size_t kRecentBytes = size_t{1} << 30;
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  kept.used = ++recent_tick_;
  if (!recent_.emplace(key, std::move(kept)).second) return image;
  recent_bytes_ += bytes;
  while (recent_bytes_ > kRecentBytes && recent_.size() > 1) {
    auto oldest = recent_.begin();
    for (auto it = recent_.begin(); it != recent_.end(); ++it)
      if (it->second.used < oldest->second.used) oldest = it;
    recent_bytes_ -= 3 * oldest->second.image.ao.size() * sizeof(float);
    recent_.erase(oldest);
  }
  return image;
}

ReferenceImage ReferenceStore::reference_image(const SceneData& s, const View& view,
                                               const Camera& camera, const GBuffer& g,
                                               const ReferenceSettings& settings,
                                               const std::vector<AoDefinition>& companions) {
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    const auto it = untaken_.find(reference_cache_key(s.content_hash, camera, settings));
    if (it != untaken_.end()) {
      ReferenceImage image = std::move(it->second);
      untaken_.erase(it);
      return image;
    }
    // Handed to the writer and not on disk yet (taken from untaken_ already).
    const auto pending = pending_.find(reference_cache_key(s.content_hash, camera, settings));
    if (pending != pending_.end()) return as_read_back(*pending->second);
  }
  if (!disk_cache_) return trace_references(s, view, camera, g, settings, companions);
  const std::string cache_key = reference_cache_key(s.content_hash, camera, settings);
  const std::string path = reference_cache_path(cache_key);
  // Shards on other nodes may need the same entry at the same moment: computed once under the
  // entry's lock (references/cache_lock.h), then read back like any hit. A hit is read once, for
  // its check and its use.
  std::optional<ReferenceImage> hit, traced;
  fill_cache_entry_once(
      path,
      [&] {
        const auto timer = stages_.time("reference read (cache)");
        hit = read_usable_cache_entry(path, cache_key);
        return hit.has_value();
      },
      [&] {
        const ReferenceImage r = trace_references(s, view, camera, g, settings, companions);
        const auto timer = stages_.time("reference write (cache)");
        const OIIO::ImageBuf written = reference_to_image(r, false);
        Attributes attributes =
            reference_attributes(s.scene, s.content_hash, view, camera, settings);
        add_cache_attributes(attributes, cache_key, written);
        write_exr(path, written, attributes, kCacheCompression);
        traced = as_read_back(r);  // what reading the entry back would give, without the read
      });
  if (hit) return std::move(*hit);
  if (traced) return std::move(*traced);
  const auto timer = stages_.time("reference read (cache)");
  return read_reference_image(path);
}

const flip::ReferenceSide& ReferenceStore::flip_reference(const GBuffer& g,
                                                          const ReferenceImage& reference) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  // References live in references_ (a std::map: stable addresses) for the session's lifetime, and
  // each belongs to one G-buffer, so the address names the (reference, mask) pair.
  auto it = flip_references_.find(&reference);
  if (it != flip_references_.end()) return it->second;
  // About 100 bytes a pixel (12 double planes): a bound keeps a paper-sized suite's references
  // from holding gigabytes; past it the cache starts again (the work is redone, not wrong).
  constexpr size_t kCacheBytes = size_t{1} << 30;
  const size_t bytes = g.pixel_count() * (12 * sizeof(double) + 1);
  if ((flip_references_.size() + 1) * bytes > kCacheBytes) flip_references_.clear();
  const std::vector<uint8_t> mask = compared_pixels(g, reference);
  return flip_references_[&reference] =
             flip::prepare_reference(g.width, g.height, reference.ao.data(), mask.data());
}

namespace {
// Added to a FLIP frame side's tick once another scoring reused it, so that the sides never reused
// go first (least recently used first among them), then the reused ones. A view's points run one
// after another, each over every frame: its true-AO sides are reused by every point, a matched
// definition's often by one point only. With plain LRU a 48-frame view's hbao-split point (48
// true-AO sides kept, 48 of its own added) pushed out the true-AO sides the next point needs,
// and from there every side was prepared again.
constexpr uint64_t kReused = uint64_t{1} << 62;
}  // namespace

std::shared_ptr<const flip::ReferenceSide> ReferenceStore::flip_frame_reference(
    const std::string& key, const GBuffer& g, const ReferenceImage& reference) {
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    const auto it = recent_flip_.find(key);
    if (it != recent_flip_.end()) {
      it->second.used = kReused + ++recent_tick_;
      return it->second.side;
    }
  }
  // Prepared without the lock (the runner's thread may ask the store for references meanwhile).
  const std::vector<uint8_t> mask = compared_pixels(g, reference);
  auto side = std::make_shared<const flip::ReferenceSide>(
      flip::prepare_reference(g.width, g.height, reference.ao.data(), mask.data()));
  const size_t bytes = g.pixel_count() * (12 * sizeof(double) + 1);
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!recent_flip_.emplace(key, RecentFlip{side, bytes, ++recent_tick_}).second) return side;
  recent_flip_bytes_ += bytes;
  while (recent_flip_bytes_ > kFlipFramesBytes && recent_flip_.size() > 1) {
    auto oldest = recent_flip_.begin();
    for (auto it = recent_flip_.begin(); it != recent_flip_.end(); ++it)
      if (it->second.used < oldest->second.used) oldest = it;
    recent_flip_bytes_ -= oldest->second.bytes;
    recent_flip_.erase(oldest);
  }
  return side;
}

}  // namespace aoeval
