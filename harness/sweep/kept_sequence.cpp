#include "harness/sweep/kept_sequence.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "base/text_files.h"
#include "harness/evaluation/background_lane.h"
#include "harness/results/results_store.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

// The point's flicker and lag maps (harness/scoring/temporal.h) as one EXR: channels flicker, lag
// and A (1 where the flicker map has a value: the pixel was compared in two successive frames);
// a pixel a map never counted holds 0. Written by write_compact_maps.
OIIO::ImageBuf maps_image(const Measurement& m) {
  OIIO::ImageSpec spec(m.width, m.height, 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"flicker", "lag", "A"};
  OIIO::ImageBuf image(spec);
  std::vector<float> pixels(m.flicker_map.size() * 3);
  for (size_t p = 0; p < m.flicker_map.size(); ++p) {
    const float f = m.flicker_map[p], l = p < m.lag_map.size() ? m.lag_map[p] : 0.0f;
    pixels[3 * p] = std::isfinite(f) ? f : 0.0f;
    pixels[3 * p + 1] = std::isfinite(l) ? l : 0.0f;
    pixels[3 * p + 2] = std::isfinite(f) ? 1.0f : 0.0f;
  }
  image.set_pixels(image.roi(), OIIO::TypeDesc::FLOAT, pixels.data());
  return image;
}

}  // namespace

std::vector<KeptImage> keep_sequence(const std::string& out, const std::string& base,
                                     const SweepPoint& p, const Measurement& m,
                                     EvaluationSession& session, KeptReferences& references,
                                     bool keep_frames) {
  // The point's folder relative to <out>: where frames.csv goes.
  const fs::path dir_rel =
      fs::path(frames_csv_path(base.empty() ? "." : base, p.name)).parent_path().lexically_normal();
  const View& view = *m.view;
  const AoDefinition definition = p.estimator->definition(m.params);
  nlohmann::json manifest = {{"run_name", p.name},
                             {"frames", view.frame_count()},
                             {"fps", view.sequence ? view.sequence->fps : 0.0},
                             {"width", m.width},
                             {"height", m.height}};
  nlohmann::json kept = nlohmann::json::array();
  std::vector<KeptImage> images;
  for (const KeptFrame& f : keep_frames ? m.kept_frames : std::vector<KeptFrame>{}) {
    const std::string estimate = (dir_rel / frame_file_name(f.frame)).string();
    if (references.exact())
      write_exr((fs::path(out) / estimate).string(), f.estimate, f.attributes);
    else
      write_half_precision_exr((fs::path(out) / estimate).string(),
                               only_channels(f.estimate, {"A", "AO"}, estimate), f.attributes);
    nlohmann::json entry = {{"frame", f.frame}, {"estimate", estimate}};
    images.push_back({frame_image_role(f.frame, "estimate"), estimate});
    if (!f.reference_cache.empty()) {
      const std::string reference = references.keep_frame(session, p.scene, view, m.width, m.height,
                                                          definition, f.frame, f.reference_cache);
      entry["reference"] = reference;
      images.push_back({frame_image_role(f.frame, "reference"), reference});
    }
    kept.push_back(entry);
    BackgroundLane::checkpoint();  // a timed frame loop may wait for no more than one frame
  }
  manifest["kept"] = kept;
  if (keep_frames && !m.flicker_map.empty()) {
    const std::string maps = (dir_rel / "maps.exr").string();
    const OIIO::ImageBuf image = maps_image(m);
    const Attributes attributes = {{"aoeval:run_name", p.name}};
    if (references.exact())
      write_exr((fs::path(out) / maps).string(), image, attributes, "zip");
    else
      write_compact_maps((fs::path(out) / maps).string(), image, attributes);
    manifest["maps"] = maps;
    images.push_back({"maps", maps});
  }
  nlohmann::json by_frame = nlohmann::json::array(), disoccluded = nlohmann::json::array();
  nlohmann::json true_by_frame = nlohmann::json::array();
  for (const auto& f : m.frames) {
    by_frame.push_back(f.value("rmse_excess", nlohmann::json()));
    true_by_frame.push_back(f.value("true_rmse_excess", nlohmann::json()));
    disoccluded.push_back(f.value("disoccluded_pixels", 0));
  }
  manifest["rmse_excess_by_frame"] = by_frame;
  manifest["true_rmse_excess_by_frame"] = true_by_frame;  // the report's overlay: one truth
  manifest["disoccluded_pixels"] = disoccluded;
  nlohmann::json by_age = nlohmann::json::array();
  for (const auto& [age, excess] : m.rmse_excess_by_age)
    by_age.push_back(
        {{"age", age},
         {"rmse_excess", std::isfinite(excess) ? nlohmann::json(excess) : nlohmann::json()}});
  manifest["rmse_excess_by_age"] = by_age;
  nlohmann::json settle = nlohmann::json::array();  // settle_frames' trajectories, ages 0..12
  for (const auto& [age, excess] : m.settle_excess_by_age)
    settle.push_back(
        {{"age", age},
         {"rmse_excess", std::isfinite(excess) ? nlohmann::json(excess) : nlohmann::json()}});
  manifest["settle_excess_by_age"] = settle;
  const std::string manifest_rel = (dir_rel / "sequence.json").string(),
                    frames_rel = (dir_rel / "frames.csv").string();
  write_text((fs::path(out) / manifest_rel).string(), manifest.dump(1) + "\n");
  write_text((fs::path(out) / frames_rel).string(), frames_csv(m.frames));
  images.push_back({"sequence", manifest_rel});
  images.push_back({"frames", frames_rel});
  return images;
}

}  // namespace aoeval
