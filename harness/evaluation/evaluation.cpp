// The thin session: a request's identity, measure() and score() over the frames of frames.cpp,
// the estimate EXR; scenes and references are its SceneCache's and ReferenceStore's.
#include "harness/evaluation/evaluation.h"

#include "base/errors.h"
#include "base/summary.h"
#include "base/version.h"
#include "estimators/registry.h"
#include "harness/evaluation/background_lane.h"
#include "harness/evaluation/frames.h"

namespace aoeval {

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
    : scenes_(stages_), references_(reference, disk_cache, scenes_, stages_), timing_(timing) {}

EvaluationSession::~EvaluationSession() = default;

void EvaluationSession::plan_references(const EvaluationRequest& req) {
  const EstimatorInfo& e = *req.estimator;
  AoDefinition definition;
  try {
    definition =
        e.definition(resolve_params(e.name, e.params, req.overrides, "estimator " + e.name));
  } catch (const InputError&) {
    return;  // the point's own run reports it
  }
  references_.plan(req.scene, req.view, req.width, req.height, {definition, true_ao_definition()});
}

void EvaluationSession::write_estimate(const Measurement& m, const std::string& path) {
  const auto timer = stages_.time("estimate EXR");
  const View& view = *m.view;
  const SceneData& s = frame_scene(m.scene, view, still_frame(view));
  const GBuffer& g = gbuffer(m.scene, view, m.width, m.height);
  Attributes a = estimate_attributes(s.scene, s.content_hash, view, g.camera, *m.estimator,
                                     m.params, m.derived);
  if (view.sequence) a.emplace_back("aoeval:frame", std::to_string(still_frame(view)));
  const OIIO::ImageBuf image = estimate_to_image(g, m.result);
  if (estimate_writer_)
    estimate_writer_(path, image, a);
  else
    write_exr(path, image, a);
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
  row.reference = reference_spec().to_json();
  row.backend = backend_name(e.backend);
  row.device = backend_device(e.backend);  // "" = the CPU; runners fill in the machine's
  row.aoeval_version = kAoevalVersion;
  row.estimator_version = estimator_code_version(e);
}

Measurement EvaluationSession::measure(const EvaluationRequest& req) {
  Measurement m;
  fill_identity(m, req);
  plan_references(req);  // its matched and true references share their rays
  const View& view = *m.view;
  ResultRow& row = m.row;
  // A still view that shows no surface at this size (the camera looks past the scene) has nothing
  // to score: its row says so, and the sweep or suite goes on with the other points.
  if (!view.sequence) {
    const GBuffer& g = gbuffer(req.scene, view, m.width, m.height);
    bool any_covered = false;
    for (size_t k = 0; k < g.pixel_count() && !any_covered; ++k) any_covered = g.covered(k);
    if (!any_covered) {
      row.status = "skipped: scene " + row.scene + " view " + view.name + " covers no pixel at " +
                   std::to_string(m.width) + "x" + std::to_string(m.height) +
                   " (nothing of the scene is in front of its camera)";
      row.timestamp = utc_now();
      return m;
    }
  }
  try {
    run_frames(m, req.seed_per_frame);
  } catch (const EstimatorUnavailable& unavailable) {
    // The backend is missing on this machine (e.g. no Vulkan device): the row says why, with no
    // metrics or timings, and sweeps and runs carry on with the other estimators.
    row.status = std::string("skipped: ") + unavailable.what();
    row.timestamp = utc_now();
    m.result = EstimateResult{};
    m.frames.clear();
    m.kept_frames.clear();
    m.sequence.reset();
    return m;
  }
  row.timestamp = utc_now();
  return m;
}

ResultRow EvaluationSession::score(Measurement& m, const std::string& estimate_path) {
  if (m.row.status != "ok") {
    last_estimate_.clear();
    return std::move(m.row);
  }
  if (SequenceScoring* sequence = m.sequence.get()) {
    FrameToScore frame = sequence->frame;
    frame.gbuffer = sequence->gbuffer.get();
    frame.estimate = &m.result;
    frame.matched = sequence->matched.get();
    frame.truth = sequence->truth ? sequence->truth.get() : sequence->matched.get();
    score_frame(sequence, &m.row, frame);
    for (nlohmann::json& f : sequence->frames) m.frames.push_back(std::move(f));
    const TemporalScorer& matched = sequence->matched_scores;
    m.rmse_excess_by_age = matched.rmse_excess_by_age();
    m.settle_excess_by_age = matched.settle_excess_by_age();
    m.flicker_map = matched.flicker_map();
    m.lag_map = matched.lag_map();
    m.row.metrics.update(matched.scores());
    m.row.true_metrics.update(sequence->true_scores.scores());
    m.sequence.reset();
  } else {
    const View& view = *m.view;
    const int w = m.width, h = m.height;
    const ReferenceImage& matched =
        reference(m.scene, view, w, h, m.estimator->definition(m.params));
    BackgroundLane::checkpoint();
    const ReferenceImage& truth = reference(m.scene, view, w, h, true_ao_definition());
    BackgroundLane::checkpoint();
    score_frame(nullptr, &m.row,
                {.index = 0,
                 .gbuffer = &gbuffer(m.scene, view, w, h),
                 .estimate = &m.result,
                 .matched = &matched,
                 .truth = &truth});
  }
  if (!estimate_path.empty()) write_estimate(m, estimate_path);
  last_estimate_ = std::move(m.result.ao);
  return std::move(m.row);
}

}  // namespace aoeval
