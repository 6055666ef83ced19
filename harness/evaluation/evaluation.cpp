#include "harness/evaluation/evaluation.h"

#include "harness/evaluation/background_lane.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>

#include "base/errors.h"
#include "base/summary.h"
#include "base/version.h"
#include "estimators/registry.h"
#include "harness/evaluation/repetition_policy.h"
#include "harness/scoring/bent_metrics.h"
#include "harness/scoring/metrics.h"
#include "references/cache_lock.h"
#include "references/reference_cache.h"
#include "scenes/corpus.h"
#include "scenes/sequence_frame.h"

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

std::string run_name(const EstimatorInfo& e, const ParamSet& params,
                     const nlohmann::json& overrides, const std::string& scene,
                     const std::string& view, int width, int height) {
  std::string name = e.name;
  for (const auto& p : e.params)
    if (overrides.contains(p.name))
      name += "/" + p.name + ":" + format_param_value(params.json()[p.name]);
  name += "/scene:" + scene + "/view:" + view + "/" + std::to_string(width) + "x" +
          std::to_string(height);
  return name;
}

Attributes estimate_attributes(const Scene& scene, uint64_t scene_hash, const View& view,
                               const Camera& camera, const EstimatorInfo& e, const ParamSet& params,
                               const nlohmann::json& derived) {
  Attributes a = gbuffer_attributes(scene, scene_hash, view, camera);
  a.emplace_back("aoeval:estimator", e.name);
  nlohmann::json all = params.json();
  if (!derived.empty()) all["derived"] = derived;
  a.emplace_back("aoeval:params", all.dump());
  a.emplace_back("aoeval:definition", e.definition(params).to_json().dump());
  return a;
}

OIIO::ImageBuf estimate_to_image(const GBuffer& g, const EstimateResult& r) {
  std::vector<std::string> names = {"AO", "A"};
  for (const auto& [name, values] : r.extra_channels) names.push_back(name);
  OIIO::ImageSpec spec(g.width, g.height, static_cast<int>(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  OIIO::ImageBuf image(spec);
  auto* px = static_cast<float*>(image.localpixels());
  const size_t nc = names.size();
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    float* o = px + k * nc;
    o[0] = g.covered(k) ? r.ao[k] : 0.0f;
    o[1] = g.coverage[k];
    size_t c = 2;
    for (const auto& [name, values] : r.extra_channels) o[c++] = g.covered(k) ? values[k] : 0.0f;
  }
  return image;
}

EvaluationSession::EvaluationSession(ReferenceSpec reference, TimingSpec timing, bool disk_cache)
    : reference_spec_(reference), timing_(timing), disk_cache_(disk_cache) {}

EvaluationSession::~EvaluationSession() = default;

const EvaluationSession::SceneData& EvaluationSession::scene(const std::string& name) {
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  auto it = scenes_.find(name);
  if (it != scenes_.end()) return it->second;
  const auto timer = stages_.time("scene load + BVH");
  SceneData data;
  data.scene = load_scene(name);
  auto& stored = scenes_[name];
  stored.scene = std::move(data.scene);
  stored.embree = std::make_unique<EmbreeScene>(stored.scene);
  stored.content_hash = stored.scene.content_hash();
  return stored;
}

const EvaluationSession::SceneData& EvaluationSession::frame_scene(const std::string& name,
                                                                   const View& view, int frame) {
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  const SceneData& base = scene(name);
  if (!view.sequence) return base;
  const SequenceFrame f = sequence_frame(base.scene, view, frame);
  if (!f.moves_objects) return base;
  const std::string key = name + "|" + view.name + "|frame " + std::to_string(frame);
  auto it = scenes_.find(key);
  if (it != scenes_.end()) return it->second;
  const auto timer = stages_.time("scene load + BVH");
  auto& stored = scenes_[key];
  stored.scene = posed_scene(base.scene, f);
  stored.embree = std::make_unique<EmbreeScene>(stored.scene);
  stored.content_hash = stored.scene.content_hash();
  return stored;
}

Camera EvaluationSession::frame_camera_of(const std::string& name, const View& view, int frame,
                                          int w, int h) {
  return frame_camera(sequence_frame(scene(name).scene, view, frame), w, h);
}

int EvaluationSession::reference_frame(const std::string& name, const View& view, int frame) {
  if (!view.sequence) return frame;
  return unchanged_since(scene(name).scene, view, frame);
}

ReferenceSettings EvaluationSession::frame_settings(const std::string& name, const View& view,
                                                    int frame, const AoDefinition& definition) {
  const ReferenceSettings s = reference_spec_.settings(definition);
  return view.sequence ? frame_reference_settings(s, reference_frame(name, view, frame)) : s;
}

void EvaluationSession::plan_references(const EvaluationRequest& req) {
  const EstimatorInfo& e = *req.estimator;
  AoDefinition definition;
  try {
    definition =
        e.definition(resolve_params(e.name, e.params, req.overrides, "estimator " + e.name));
  } catch (const InputError&) {
    return;  // the point's own run reports it
  }
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  std::vector<AoDefinition>& planned =
      planned_[req.scene + "|" + req.view + "|" + std::to_string(req.width) + "x" +
               std::to_string(req.height)];
  for (const AoDefinition& d : {definition, true_ao_definition()})
    if (std::find(planned.begin(), planned.end(), d) == planned.end()) planned.push_back(d);
}

std::vector<AoDefinition> EvaluationSession::planned_definitions(const std::string& name,
                                                                 const View& view, int w, int h) {
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  const Scene& base = scene(name).scene;
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

namespace {
std::string view_key(const std::string& scene, const View& v, int w, int h) {
  return scene + "|" + v.name + "|" + std::to_string(w) + "x" + std::to_string(h);
}
}  // namespace

const GBuffer& EvaluationSession::gbuffer(const std::string& scene_name, const View& view, int w,
                                          int h) {
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  const std::string key = view_key(scene_name, view, w, h);
  auto it = gbuffers_.find(key);
  if (it != gbuffers_.end()) return it->second;
  const int k = still_frame(view);
  const SceneData& s = frame_scene(scene_name, view, k);
  const Camera camera = frame_camera_of(scene_name, view, k, w, h);
  const auto timer = stages_.time("G-buffer");
  return gbuffers_[key] = render_gbuffer(*s.embree, camera);
}

void EvaluationSession::compute_missing_reference(const std::string& scene_name, const View& view,
                                                  int w, int h, const AoDefinition& definition) {
  {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    const std::string key = view_key(scene_name, view, w, h) + "|" + definition.to_json().dump();
    if (references_.count(key)) return;
    if (disk_cache_) {
      const int k = still_frame(view);
      const SceneData& s = frame_scene(scene_name, view, k);
      const std::string path = reference_cache_path(
          reference_cache_key(s.content_hash, frame_camera_of(scene_name, view, k, w, h),
                              frame_settings(scene_name, view, k, definition)));
      if (fs::exists(path)) return;  // read when scored (a damaged entry is recomputed then)
    }
  }
  reference(scene_name, view, w, h, definition);
}

const ReferenceImage& EvaluationSession::reference(const std::string& scene_name, const View& view,
                                                   int w, int h, const AoDefinition& definition) {
  const std::string key = view_key(scene_name, view, w, h) + "|" + definition.to_json().dump();
  {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    auto it = references_.find(key);
    if (it != references_.end()) return it->second;
  }
  // Read or computed without the lock: the background lane reads references while the runner's
  // thread asks whether the next point's are cached, and a lock held through a 15 ms EXR read
  // made the runner wait (issue 16). Only the runner's thread computes (compute_missing_reference,
  // before a point's frames, and the lane scores points whose references exist), so two threads
  // at most read the same file twice; the first copy stored wins.
  const int k = still_frame(view);
  const SceneData& s = frame_scene(scene_name, view, k);
  const GBuffer& g = gbuffer(scene_name, view, w, h);
  ReferenceImage image =
      reference_image(s, view, g.camera, g, frame_settings(scene_name, view, k, definition),
                      planned_definitions(scene_name, view, w, h));
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
  return references_.emplace(key, std::move(image)).first->second;
}

namespace {
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

ReferenceImage EvaluationSession::trace_references(const SceneData& s, const View& view,
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
      if (disk_cache_ ? fs::exists(reference_cache_path(key)) : untaken_.count(key) != 0) continue;
      batch.push_back(d);
      keys.push_back(key);
    }
  std::vector<ReferenceImage> traced;
  {
    const auto timer = stages_.time("reference compute");
    traced = compute_references(*s.embree, g, settings, batch);
  }
  {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    counts_.traces += 1;
    counts_.references += batch.size();
    counts_.rays += traced[0].rays_traced;
  }
  // The companions' entries, each complete before it is renamed into place (write_exr is atomic):
  // a shard that traced the same entry meanwhile wrote the same bits.
  for (size_t i = 1; disk_cache_ && i < batch.size(); ++i) {
    const auto timer = stages_.time("reference write (cache)");
    ReferenceSettings other = settings;
    other.definition = batch[i];
    const OIIO::ImageBuf written = reference_to_image(traced[i], false);
    Attributes attributes = reference_attributes(s.scene, s.content_hash, view, camera, other);
    add_cache_attributes(attributes, keys[i], written);
    write_exr(reference_cache_path(keys[i]), written, attributes);
  }
  // The companions wait in memory for their one request, as their entries would read back: a
  // cold run does not read what it has just traced (issue 42: 15 s of a 303 s cold default run).
  {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    for (size_t i = 1; i < batch.size(); ++i)
      untaken_[keys[i]] = as_read_back(std::move(traced[i]));
  }
  return std::move(traced[0]);
}

ReferenceImage EvaluationSession::reference_image(const SceneData& s, const View& view,
                                                  const Camera& camera, const GBuffer& g,
                                                  const ReferenceSettings& settings,
                                                  const std::vector<AoDefinition>& companions) {
  {
    std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
    const auto it = untaken_.find(reference_cache_key(s.content_hash, camera, settings));
    if (it != untaken_.end()) {
      ReferenceImage image = std::move(it->second);
      untaken_.erase(it);
      return image;
    }
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
        write_exr(path, written, attributes);
        traced = as_read_back(r);  // what reading the entry back would give, without the read
      });
  if (hit) return std::move(*hit);
  if (traced) return std::move(*traced);
  const auto timer = stages_.time("reference read (cache)");
  return read_reference_image(path);
}

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<uint8_t> compared_pixels(const GBuffer& g, const ReferenceImage& ref) {
  std::vector<uint8_t> mask(g.pixel_count());
  for (size_t k = 0; k < mask.size(); ++k) mask[k] = g.covered(k) && ref.covered(k);
  return mask;
}

nlohmann::json score_against(const GBuffer& g, const ReferenceImage& ref,
                             const std::vector<float>& est,
                             const std::optional<std::vector<glm::vec3>>& bent,
                             const std::string& prefix, const flip::ReferenceSide& flip_reference) {
  const std::vector<uint8_t> mask = compared_pixels(g, ref);
  const Metrics m =
      compare_images({g.width, g.height, ref.ao.data()}, {g.width, g.height, est.data()}, mask,
                     ref.stderr_ao, &flip_reference);
  nlohmann::json out = to_json(m, prefix);
  BackgroundLane::checkpoint();
  if (bent) {
    if (const auto b = compare_bent(g.width, g.height, ref.bent, *bent, mask, ref.bent_stderr))
      add_bent_json(*b, out, prefix);
  }
  return out;
}

const std::vector<float>* channel(const EstimateResult& r, const std::string& name) {
  const auto it = r.extra_channels.find(name);
  return it == r.extra_channels.end() ? nullptr : &it->second;
}

}  // namespace

const flip::ReferenceSide& EvaluationSession::flip_reference(const GBuffer& g,
                                                             const ReferenceImage& reference) {
  std::lock_guard<std::recursive_mutex> lock(cache_mutex_);
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

void EvaluationSession::write_estimate(const Measurement& m, const std::string& path) {
  const auto timer = stages_.time("estimate EXR");
  const View& view = *m.view;
  const SceneData& s = frame_scene(m.scene, view, still_frame(view));
  const GBuffer& g = gbuffer(m.scene, view, m.width, m.height);
  Attributes a = estimate_attributes(s.scene, s.content_hash, view, g.camera, *m.estimator,
                                     m.params, m.derived);
  if (view.sequence) a.emplace_back("aoeval:frame", std::to_string(still_frame(view)));
  write_exr(path, estimate_to_image(g, m.result), a);
}

ResultRow EvaluationSession::evaluate(const EvaluationRequest& req,
                                      const std::string& estimate_path) {
  Measurement m = measure(req);
  return score(m, estimate_path);
}

void EvaluationSession::fill_identity(Measurement& m, const EvaluationRequest& req) {
  const EstimatorInfo& e = *req.estimator;
  m.estimator = &e;
  m.params = resolve_params(e.name, e.params, req.overrides, "estimator " + e.name);
  const SceneData& s = scene(req.scene);
  const View& view = s.scene.view(req.view);
  m.scene = req.scene;
  m.view = &view;
  m.width = req.width > 0 ? req.width : view.width;
  m.height = req.height > 0 ? req.height : view.height;
  ResultRow& row = m.row;
  row.run_name = run_name(e, m.params, req.overrides, s.scene.name, view.name, m.width, m.height);
  if (view.sequence && !req.seed_per_frame) row.run_name += "/seed_per_frame:false";
  row.estimator = e.name;
  row.params = m.params.json();
  row.scene = s.scene.name;
  row.view = view.name;
  row.width = m.width;
  row.height = m.height;
  row.definition = e.definition(m.params).to_json().dump();
  row.reference = reference_spec_.to_json();
  row.backend = backend_name(e.backend);
  row.device = backend_device(e.backend);  // "" = the CPU; runners fill in the machine's
  row.aoeval_version = kAoevalVersion;
  row.estimator_version = estimator_code_version(e);
}

Measurement EvaluationSession::measure(const EvaluationRequest& req) {
  Measurement m;
  fill_identity(m, req);
  plan_references(req);  // its matched and true references share their rays
  if (m.view->sequence) {
    measure_sequence(m, req.seed_per_frame);
    return m;
  }
  const EstimatorInfo& e = *req.estimator;
  const ParamSet& params = m.params;
  const SceneData& s = scene(req.scene);
  const View& view = *m.view;
  const int w = m.width, h = m.height;
  const GBuffer& g = gbuffer(req.scene, view, w, h);
  const AoDefinition definition = e.definition(params);
  ResultRow& row = m.row;
  // A view that shows no surface at this size (the camera looks past the scene) has nothing to
  // score: its row says so, and the sweep or suite goes on with the other points.
  bool any_covered = false;
  for (size_t k = 0; k < g.pixel_count() && !any_covered; ++k) any_covered = g.covered(k);
  if (!any_covered) {
    row.status = "skipped: scene " + s.scene.name + " view " + view.name + " covers no pixel at " +
                 std::to_string(w) + "x" + std::to_string(h) +
                 " (nothing of the scene is in front of its camera)";
    row.timestamp = utc_now();
    return m;
  }

  const EstimateContext context{s.scene, *s.embree, g};
  std::unique_ptr<Estimator> estimator;
  {
    const auto timer = stages_.time("estimator set-up");
    estimator = e.create(params);
  }
  nlohmann::json& derived = m.derived;
  EstimateResult& result = m.result;
  std::vector<double> times;
  std::map<std::string, std::vector<double>> passes;
  try {
    const auto t_pre = std::chrono::steady_clock::now();
    estimator->prepare(context);
    row.precompute_ms = ms_since(t_pre);
    stages_.add(StageTimes::kEstimatorPrecompute, row.precompute_ms);
    derived = estimator->derived();
    if (!derived.empty()) row.params["derived"] = derived;
    {
      const auto timer = stages_.time(StageTimes::kEstimatorWarmup);
      for (int i = 0; i < timing_.warmup; ++i) result = estimator->run(context);
    }
    // A reference missing from the cache is computed here, on the caller's thread, not by score()
    // on a background lane, where it would run for seconds beside the estimators' frames (after
    // the warm-up, so that an estimator without its backend computes none).
    compute_missing_reference(req.scene, view, w, h, definition);
    compute_missing_reference(req.scene, view, w, h, true_ao_definition());
    if (before_timed_frames_) {
      const auto timer = stages_.time(StageTimes::kWaitingForBackground);
      before_timed_frames_();
    }
    struct AfterFrames {  // resumes the background work however the frames end
      const std::function<void()>& after;
      ~AfterFrames() {
        if (after) after();
      }
    } after_frames{after_timed_frames_};
    const auto timer = stages_.time(StageTimes::kEstimatorFrames);
    while (!enough_repetitions(timing_, times)) {
      const auto t0 = std::chrono::steady_clock::now();
      result = estimator->run(context);
      const double wall = ms_since(t0);
      const auto total = result.pass_ms.find("total_ms");
      times.push_back(total != result.pass_ms.end() ? total->second : wall);
      for (const auto& [pass, ms] : result.pass_ms) passes[pass].push_back(ms);
    }
  } catch (const EstimatorUnavailable& unavailable) {
    // The backend is missing on this machine (e.g. no Vulkan device): the row says why, with no
    // metrics or timings, and sweeps and runs carry on with the other estimators.
    row.status = std::string("skipped: ") + unavailable.what();
    row.timestamp = utc_now();
    result = EstimateResult{};
    return m;
  }
  if (result.ao.size() != g.pixel_count())
    throw std::runtime_error("estimator " + e.name + " returned " +
                             std::to_string(result.ao.size()) + " values for " +
                             std::to_string(g.pixel_count()) + " pixels");
  row.set_times(times);
  for (const auto& [pass, values] : passes)
    if (pass != "total_ms") row.pass_ms[pass] = median(values);
  row.timing_source = !result.timing_source.empty()           ? result.timing_source
                      : result.pass_ms.count("total_ms") != 0 ? "gpu-timestamps"
                                                              : "wall";
  row.timestamp = utc_now();
  return m;
}

ResultRow EvaluationSession::score(Measurement& m, const std::string& estimate_path) {
  ResultRow row = std::move(m.row);
  if (row.status != "ok") {
    last_estimate_.clear();
    return row;
  }
  if (m.scored) {  // a sequence point, scored frame by frame while it ran (sequence_evaluation.cpp)
    if (!estimate_path.empty()) write_estimate(m, estimate_path);
    last_estimate_ = std::move(m.result.ao);
    return row;
  }
  const EstimatorInfo& e = *m.estimator;
  const ParamSet& params = m.params;
  const EstimateResult& result = m.result;
  const View& view = *m.view;
  const int w = m.width, h = m.height;
  const GBuffer& g = gbuffer(m.scene, view, w, h);
  const AoDefinition definition = e.definition(params);
  const auto bent = bent_of_channels(channel(result, "bent.X"), channel(result, "bent.Y"),
                                     channel(result, "bent.Z"));
  // Between the steps a background lane may hold this thread while an estimator's frames are
  // timed (BackgroundLane::checkpoint; a no-op on the runner's own thread).
  const ReferenceImage& matched = reference(m.scene, view, w, h, definition);
  BackgroundLane::checkpoint();
  const ReferenceImage& truth = reference(m.scene, view, w, h, true_ao_definition());
  BackgroundLane::checkpoint();
  // Each scoring in two steps (FLIP's reference side, then the metrics), so that a pause waits
  // for one step, not a whole scoring (issue 16: the runner's waits for the lane).
  auto score_with = [&](const ReferenceImage& reference) {
    const flip::ReferenceSide* flip_side = nullptr;
    {
      const auto timer = stages_.time("scoring");
      flip_side = &flip_reference(g, reference);
    }
    BackgroundLane::checkpoint();
    const auto timer = stages_.time("scoring");
    return score_against(g, reference, result.ao, bent, "", *flip_side);
  };
  row.metrics = score_with(matched);
  BackgroundLane::checkpoint();
  // An estimator whose declared definition is true AO is scored against one reference twice: the
  // same inputs give the same numbers, so the second scoring is the first's copy.
  row.true_metrics = &truth == &matched ? row.metrics : score_with(truth);
  BackgroundLane::checkpoint();
  if (!estimate_path.empty()) write_estimate(m, estimate_path);
  last_estimate_ = std::move(m.result.ao);
  return row;
}

}  // namespace aoeval
