// The references of a session: in memory, in the disk cache (references/reference_cache.h), and
// traced, several definitions of one weighting in one pass when the runs declared them
// (plan_references, issue 42); with FLIP's reference side of each one scored against.
// Thread-safe as EvaluationSession needs (evaluation.h): the runner's thread traces, the
// background lane reads.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "harness/evaluation/scene_cache.h"
#include "harness/scoring/flip.h"
#include "references/reference.h"

namespace aoeval {

// The reference of a sweep or suite; its defaults are ReferenceSettings' (references/reference.h).
struct ReferenceSpec {
  int spp = ReferenceSettings{}.spp;
  SamplerKind sampler = ReferenceSettings{}.sampler;
  uint64_t seed = ReferenceSettings{}.seed;
  nlohmann::json to_json() const;
  // The reference's settings for one AO definition.
  ReferenceSettings settings(const AoDefinition& definition) const;
};

class ReferenceStore {
 public:
  // `stages` receives "reference compute", "reference read (cache)" and "reference write (cache)".
  ReferenceStore(ReferenceSpec spec, bool disk_cache, SceneCache& scenes, StageTimes& stages)
      : spec_(spec), disk_cache_(disk_cache), scenes_(scenes), stages_(stages) {}

  const ReferenceSpec& spec() const { return spec_; }
  bool disk_cache() const { return disk_cache_; }
  // Frame k's reference settings: seed + j for sequence views, where j = reference_frame().
  ReferenceSettings frame_settings(const std::string& scene, const View& view, int frame,
                                   const AoDefinition& definition);
  // Declares definitions a request of (scene, view, WxH) will ask for, as the request names them
  // (view "" = the scene's first, size 0 = the view's own).
  void plan(const std::string& scene, const std::string& view, int w, int h,
            const std::vector<AoDefinition>& definitions);
  // The definitions declared for a view at a size (view "" and size 0 of requests resolved).
  std::vector<AoDefinition> planned_definitions(const std::string& scene, const View& view, int w,
                                                int h);
  // What the store traced: passes over the rays, the reference images they gave (a pass gives
  // one per definition it shares its rays with) and the rays.
  struct Counts {
    uint64_t traces = 0, references = 0, rays = 0;
  };
  Counts counts() {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    return counts_;
  }
  // The reference of a G-buffer `g` of scene `s` seen by `camera`: from the disk cache (keyed by
  // the scene's geometry, the camera and the settings) or computed and stored there.
  // `companions`: definitions to trace with it when it is traced (their cache entries written too).
  ReferenceImage reference_image(const SceneData& s, const View& view, const Camera& camera,
                                 const GBuffer& g, const ReferenceSettings& settings,
                                 const std::vector<AoDefinition>& companions = {});
  // The reference of a view's still frame at a size, kept in memory for the session.
  const ReferenceImage& reference(const std::string& scene, const View& view, int width, int height,
                                  const AoDefinition& definition);
  // A sequence frame's reference_image(), served from memory when another point asked for it
  // before (the points of one sequence ask for the same frames' references; a cold default run
  // read 9.4 s of them back from the disk cache, issue 42). What is kept is what a sequence frame
  // is scored on (AO, its standard error, A: the same scores), least recently used out first past
  // about 1 GiB.
  ReferenceImage frame_reference(const SceneData& s, const View& view, const Camera& camera,
                                 const GBuffer& g, const ReferenceSettings& settings,
                                 const std::vector<AoDefinition>& companions = {});
  // Where the cache entries of traced companions are written: `post` runs a job later (the
  // runners' background lane, whose pause guards the timed frames); empty, or on a lane's own
  // thread, they are written at once. Until written, an entry is served from memory.
  void set_writer(std::function<void(std::function<void()>)> post) {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    writer_ = std::move(post);
  }
  // reference() traced now when it is neither in memory nor in the disk cache (the runner's
  // thread computes; scoring on the background lane then only reads).
  void compute_missing(const std::string& scene, const View& view, int w, int h,
                       const AoDefinition& definition);
  // FLIP's reference side of a reference() against `g` (flip::prepare_reference), cached.
  const flip::ReferenceSide& flip_reference(const GBuffer& g, const ReferenceImage& reference);
  // FLIP's reference side of a sequence frame's reference `reference` (cache key `key`: the same
  // key is the same image, from memory, the disk cache or a trace) against the frame's `g`, kept
  // for the other points of the view: they score against the same frames (issue 42: prepared once
  // per frame and definition instead of once per point and frame; the same bits, flip.h). Least
  // recently used out past kFlipFramesBytes; compare_images() checks its mask before using it.
  std::shared_ptr<const flip::ReferenceSide> flip_frame_reference(const std::string& key,
                                                                  const GBuffer& g,
                                                                  const ReferenceImage& reference);
  // About 7.4 MB a 320x240 frame (12 double planes): the true-AO side of a 48-frame view fits.
  static constexpr size_t kFlipFramesBytes = size_t{512} << 20;

 private:
  ReferenceSpec spec_;
  bool disk_cache_;
  SceneCache& scenes_;
  StageTimes& stages_;
  // Guards the maps below (std::map: entries never move or vanish, except FLIP's).
  std::recursive_mutex mutex_;
  std::map<std::string, ReferenceImage> references_;
  std::map<std::string, std::vector<AoDefinition>> planned_;  // "scene|view|WxH" as requested
  Counts counts_;
  // Images traced as companions, by cache key, as their entries read back, until asked for once
  // (with a disk cache too: a cold run does not read what it has just traced).
  std::map<std::string, ReferenceImage> untaken_;
  std::map<const ReferenceImage*, flip::ReferenceSide> flip_references_;
  // flip_frame_reference()'s memory, by cache key.
  struct RecentFlip {
    std::shared_ptr<const flip::ReferenceSide> side;
    size_t bytes = 0;
    uint64_t used = 0;
  };
  std::map<std::string, RecentFlip> recent_flip_;
  size_t recent_flip_bytes_ = 0;
  std::function<void(std::function<void()>)> writer_;
  // Companions handed to writer_ and not on disk yet, as traced, by cache key.
  std::map<std::string, std::shared_ptr<const ReferenceImage>> pending_;
  // frame_reference()'s memory, by cache key.
  struct Recent {
    ReferenceImage image;
    uint64_t used = 0;
  };
  std::map<std::string, Recent> recent_;
  size_t recent_bytes_ = 0;
  uint64_t recent_tick_ = 0;
  // Writes a traced companion's cache entry, now or through writer_.
  void write_companion(const SceneData& s, const View& view, const Camera& camera,
                       const ReferenceSettings& settings, const std::string& key,
                       ReferenceImage traced);
  // Traces `settings`' reference with those companions of its weighting not yet in the disk cache,
  // writes the companions' entries and returns the asked one.
  ReferenceImage trace_references(const SceneData& s, const View& view, const Camera& camera,
                                  const GBuffer& g, const ReferenceSettings& settings,
                                  const std::vector<AoDefinition>& companions);
};

// The pixels a reference is compared on against a G-buffer: covered in both.
std::vector<uint8_t> compared_pixels(const GBuffer& g, const ReferenceImage& reference);

}  // namespace aoeval
