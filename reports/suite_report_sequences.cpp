#include "reports/suite_report_sequences.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/errors.h"
#include "base/text_files.h"
#include "drawing/error_maps.h"
#include "drawing/plot.h"
#include "harness/results/results_store.h"
#include "reports/html.h"
#include "reports/suite_report_leaderboard.h"
#include "reports/suite_report_mosaics.h"
#include "reports/suite_report_sequences_summary.h"
#include "reports/viewer.h"
#include "scenes/ao_exr.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

const float kCanvas[3] = {0.12f, 0.12f, 0.12f};  // the error maps' dark canvas
constexpr int kGap = 4;

// Images side by side (or one above the other), top- (left-) aligned on the dark canvas.
OIIO::ImageBuf stack(const std::vector<OIIO::ImageBuf>& parts, bool across) {
  int w = 0, h = 0;
  for (const auto& p : parts) {
    const OIIO::ROI r = p.roi();
    w = across ? w + r.width() + (w ? kGap : 0) : std::max(w, r.width());
    h = across ? std::max(h, r.height()) : h + r.height() + (h ? kGap : 0);
  }
  OIIO::ImageBuf out(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  OIIO::ImageBufAlgo::fill(out, {kCanvas[0], kCanvas[1], kCanvas[2]});
  int at = 0;
  for (const auto& p : parts) {
    OIIO::ImageBufAlgo::paste(out, across ? at : 0, across ? 0 : at, 0, 0, p);
    at += (across ? p.roi().width() : p.roi().height()) + kGap;
  }
  return out;
}

// One kept frame's pair of images, read through the one AO-EXR reader.
struct FramePair {
  int frame = 0;
  AoExr ref, est;
  std::vector<uint8_t> mask;
};
FramePair read_pair(const fs::path& out, const nlohmann::json& kept) {
  FramePair p;
  p.frame = kept.at("frame").get<int>();
  p.ref = read_ao_exr((out / kept.at("reference").get<std::string>()).string());
  p.est = read_ao_exr((out / kept.at("estimate").get<std::string>()).string());
  if (p.ref.width != p.est.width || p.ref.height != p.est.height)
    throw InputError(p.est.path + ": not the size of " + p.ref.path);
  p.mask.resize(p.ref.ao.size());
  for (size_t k = 0; k < p.mask.size(); ++k) p.mask[k] = p.ref.covered(k) && p.est.covered(k);
  return p;
}

// The strip's frames (indices into `kept`): the first, the one with most disoccluded pixels
// (the middle one when nothing was disoccluded: a static camera) and the last.
std::vector<size_t> strip_frames(const nlohmann::json& kept, const nlohmann::json& disoccluded) {
  size_t heavy = kept.size() / 2;
  int most = 0;
  for (size_t i = 1; i < kept.size(); ++i) {
    const int k = kept[i]["frame"].get<int>();
    const int n = k < static_cast<int>(disoccluded.size()) ? disoccluded[k].get<int>() : 0;
    if (n > most) {
      most = n;
      heavy = i;
    }
  }
  std::vector<size_t> pick = {0, heavy, kept.size() - 1};
  pick.erase(std::unique(pick.begin(), pick.end()), pick.end());
  return pick;
}

// reference | estimate | |error| per strip frame, one error scale for all; returns the scale.
float draw_strip(const fs::path& out, const nlohmann::json& kept, const std::vector<size_t>& pick,
                 const fs::path& png) {
  std::vector<FramePair> pairs;
  float p99 = 0.0f;
  for (size_t i : pick) {
    pairs.push_back(read_pair(out, kept[i]));
    const FramePair& f = pairs.back();
    p99 = std::max(
        p99, abs_error_p99(f.ref.width, f.ref.height, f.ref.ao.data(), f.est.ao.data(), f.mask));
  }
  const float scale = nice_ceiling(p99);
  std::vector<OIIO::ImageBuf> rows;
  for (const FramePair& f : pairs) {
    const int w = f.ref.width, h = f.ref.height;
    const std::string frame = "frame " + std::to_string(f.frame);
    rows.push_back(stack({ao_image(w, h, f.ref.ao.data(), f.mask, "reference, " + frame),
                          ao_image(w, h, f.est.ao.data(), f.mask, "estimate, " + frame),
                          abs_error_map(w, h, f.ref.ao.data(), f.est.ao.data(), f.mask, scale)},
                         true));
  }
  write_image(png.string(), stack(rows, false));
  return scale;
}

// rmse_excess by frame (steady_rmse_excess dashed over the frames it averages) | by frames since
// disocclusion.
PlotSpec chart_of(const nlohmann::json& manifest, const ResultRow& row) {
  PlotSpec by_frame, by_age;
  by_frame.title = "rmse_excess by frame";
  by_frame.x_label = "frame";
  by_frame.y_label = "rmse_excess (matched reference)";
  PlotSeries frames;
  frames.label = "rmse_excess";
  const auto& values = manifest["rmse_excess_by_frame"];
  for (size_t k = 0; k < values.size(); ++k)
    if (values[k].is_number()) {
      frames.x.push_back(static_cast<double>(k));
      frames.y.push_back(values[k].get<double>());
    }
  by_frame.series.push_back(frames);
  const auto steady = row.metrics.find("steady_rmse_excess");
  if (steady != row.metrics.end() && steady->is_number() && !values.empty()) {
    PlotSeries s;
    s.label = "steady_rmse_excess";
    s.dashed = true;
    s.x = {std::floor(values.size() / 2.0), static_cast<double>(values.size() - 1)};
    s.y = {steady->get<double>(), steady->get<double>()};
    by_frame.series.push_back(s);
  }
  by_age.title = "rmse_excess by frames since disocclusion";
  by_age.x_label = "frames since the pixel was disoccluded";
  by_age.y_label = "rmse_excess";
  PlotSeries ages;
  ages.marker = "o";
  for (const auto& a : manifest["rmse_excess_by_age"])
    if (a["rmse_excess"].is_number()) {
      ages.x.push_back(a["age"].get<double>());
      ages.y.push_back(a["rmse_excess"].get<double>());
    }
  PlotSeries still;  // settle_frames' pool: trajectories whose truth holds still, ages 0..12
  still.label = "trajectories whose truth holds still (settle_frames)";
  still.marker = "s";
  still.dashed = true;
  for (const auto& a : manifest.value("settle_excess_by_age", nlohmann::json::array()))
    if (a["rmse_excess"].is_number()) {
      still.x.push_back(a["age"].get<double>());
      still.y.push_back(a["rmse_excess"].get<double>());
    }
  if (ages.x.empty())
    by_age.notes.push_back("no pixel was disoccluded");
  else
    by_age.series.push_back(ages);
  if (!still.x.empty()) {
    if (!by_age.series.empty()) by_age.series.front().label = "every pixel of that age";
    by_age.series.push_back(still);
  }
  PlotSpec spec;
  spec.title = row.run_name;
  spec.width_in = 10.0;
  spec.height_in = 3.6;
  spec.panels = {by_frame, by_age};
  return spec;
}

Html value_of(const nlohmann::json& metrics, const std::string& key) {
  const auto it = metrics.find(key);
  if (it == metrics.end() || !it->is_number()) return Html("&ndash;");
  return number(it->get<double>());
}

Html link(const std::string& href, const std::string& label) {
  return Html("<a href=\"") << url(href) << "\">" << text(label) << "</a>";
}

// One sequence point's section as the first pass gathers it: what its drawings read and where
// they go.
struct PointDrawing {
  const SuiteReportEntry* entry = nullptr;
  const ResultRow* row = nullptr;
  std::string manifest_rel;  // the manifest's path in the store (its role "sequence")
  fs::path dir, manifest_path;
  nlohmann::json manifest, kept;  // kept: the frames with both images
  std::vector<std::string> refs, ests;
  std::vector<int> numbers;
  std::vector<fs::path> sources;
  std::vector<size_t> pick;
  ViewerSpec spec;
};

// Draws a point's strip when older than its sources, and writes its estimate's viewer data (its
// reference's: reference_data), which its video plays too (viewer.h video_html).
void draw_point(const fs::path& out, PointDrawing& p) {
  if (p.kept.empty()) return;
  const fs::path strip = out / p.dir / "strip.png";
  if (!up_to_date(strip, p.sources)) draw_strip(out, p.kept, p.pick, strip);
  std::error_code gone;
  fs::remove(out / p.dir / "video.png", gone);  // an older aoeval's animated PNG of the same frames
  p.spec.b = write_viewer_data(out.string(), p.ests, estimate_viewer_channels(), p.numbers,
                               p.manifest.value("fps", 0.0));
}

// The reference viewer data of every point, each distinct reference sequence written once (points
// of one view and definition share it; two threads must not write one file).
void reference_data(const fs::path& out, std::vector<PointDrawing>& drawings) {
  std::map<std::vector<std::string>, std::vector<PointDrawing*>> by_refs;
  for (PointDrawing& p : drawings)
    if (!p.kept.empty()) by_refs[p.refs].push_back(&p);
  std::vector<std::vector<PointDrawing*>> groups;
  for (auto& [refs, group] : by_refs) groups.push_back(group);
  tbb::parallel_for(size_t{0}, groups.size(), [&](size_t i) {
    const PointDrawing& first = *groups[i].front();
    const std::string data =
        write_viewer_data(out.string(), first.refs, reference_viewer_channels(), first.numbers,
                          first.manifest.value("fps", 0.0));
    for (PointDrawing* p : groups[i]) p->spec.a = data;
  });
}

}  // namespace

Html sequence_sections(const std::string& out_dir, const SuiteReport& report) {
  const fs::path out(out_dir);
  // First pass: every point's manifest and kept frames (serial: cheap).
  std::vector<PointDrawing> drawings;
  for (const auto& e : report.entries) {
    const ResultRow& r = e.row;
    if (r.status != "ok" || !r.metrics.contains("seq_frames")) continue;
    PointDrawing p;
    p.entry = &e;
    p.row = &r;
    // The point's manifest, by its role in the store; its folder holds the page's drawings too.
    const std::string manifest_rel = e.image("sequence");
    std::error_code ec;
    if (manifest_rel.empty() || !fs::exists(out / manifest_rel, ec))
      continue;  // rows of an older aoeval: no manifest in the store
    p.manifest_rel = manifest_rel;
    p.dir = fs::path(manifest_rel).parent_path();
    p.manifest_path = out / manifest_rel;
    try {
      std::ifstream in(p.manifest_path);
      p.manifest = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& x) {
      throw InputError(p.manifest_path.string() + ": not a sequence manifest (" + x.what() + ")");
    }
    p.kept = nlohmann::json::array();
    for (const auto& k : p.manifest.value("kept", nlohmann::json::array()))
      if (k.contains("reference") && fs::exists(out / k["estimate"].get<std::string>(), ec) &&
          fs::exists(out / k["reference"].get<std::string>(), ec))
        p.kept.push_back(k);
    p.sources = {p.manifest_path};
    for (const auto& k : p.kept) {
      p.refs.push_back(k["reference"].get<std::string>());
      p.ests.push_back(k["estimate"].get<std::string>());
      p.numbers.push_back(k["frame"].get<int>());
      p.sources.push_back(out / p.refs.back());
      p.sources.push_back(out / p.ests.back());
    }
    if (!p.kept.empty())
      p.pick =
          strip_frames(p.kept, p.manifest.value("disoccluded_pixels", nlohmann::json::array()));
    drawings.push_back(std::move(p));
  }
  // The drawings and viewer data: each point's files are its own, so the points run in
  // parallel (issue 42: the report stage was serial; most of it is these EXR reads and
  // encodings).
  reference_data(out, drawings);
  tbb::parallel_for(size_t{0}, drawings.size(), [&](size_t i) { draw_point(out, drawings[i]); });
  // Then the page, in the entries' order.
  Html h;
  std::vector<std::pair<PlotSpec, std::string>> charts;
  std::vector<SequencePoint> points;
  for (const PointDrawing& p : drawings) {
    const SuiteReportEntry& e = *p.entry;
    const ResultRow& r = *p.row;
    const std::string& manifest_rel = p.manifest_rel;
    const fs::path& dir = p.dir;
    const fs::path& manifest_path = p.manifest_path;
    const nlohmann::json& m = p.manifest;
    const nlohmann::json& kept = p.kept;
    points.push_back({&r, m, dir.string()});
    // Folded (a reader opens the points they look at: the page stays short); a link to the
    // section's id unfolds it (the browser opens a <details> holding a fragment's target).
    h << "<details class=\"sequence-point\"><summary>" << text(r.estimator) << " "
      << text(params_of(r)) << ", " << text(r.scene) << "/" << text(r.view) << " " << r.width
      << "&times;" << r.height << ", " << m.value("frames", 0)
      << " frames: true steady_rmse_excess " << number(true_score(r))
      << "</summary>\n<section class=\"sequence\" id=\"sequence-" << attr(slug(r.run_name))
      << "\"><table class=\"metrics\"><tr>";
    for (const auto& k : sequence_metric_names()) h << "<th>" << text(k) << "</th>";
    h << "</tr>\n<tr>";
    for (const auto& k : sequence_metric_names()) h << "<td>" << value_of(r.metrics, k) << "</td>";
    h << "</tr></table>\n";
    if (!kept.empty()) {
      const std::string strip = (dir / "strip.png").string();
      std::string picked;
      for (size_t i : p.pick) picked += (picked.empty() ? "" : ", ") + std::to_string(p.numbers[i]);
      h << "<figure>"
        << viewer_html(p.spec, Html("<img class=\"mosaic strip\" src=\"")
                                   << url(strip) << "\" loading=\"lazy\" alt=\""
                                   << attr(r.run_name + ": frames " + picked) << "\">")
        << "<figcaption>Frames " << text(picked)
        << " (the first, the one with most disoccluded pixels, the last): reference | estimate | "
           "|estimate &minus; reference|, one error scale for the three. The viewer holds all "
        << kept.size() << " kept frames (frame slider, play: , . p).</figcaption></figure>\n"
        << "<figure>" << video_html(p.spec, m.value("fps", 0.0), manifest_rel)
        << "<figcaption>Reference | estimate, every kept frame at " << value_of(m, "fps")
        << " frames per second, drawn from the viewer's data when it comes into view (play / "
           "pause).</figcaption></figure>\n";
    }
    h << sequence_maps_figure(out_dir, points.back());
    const std::string chart = (dir / "rmse_excess.png").string();
    if (!up_to_date(out / chart, {manifest_path}))
      charts.emplace_back(chart_of(m, r), (out / chart).string());
    h << "<figure><img class=\"chart\" src=\"" << url(chart) << "\" loading=\"lazy\" alt=\""
      << attr(r.run_name) << ": rmse_excess by frame and by frames since disocclusion\">"
      << "<figcaption>Left: each frame's rmse_excess, steady_rmse_excess dashed over the frames it "
         "averages (the last half). Right: rmse_excess over pixels grouped by the frames since "
         "they were last disoccluded (settle_frames is the first age within 1.1 &times; "
         "steady).</figcaption></figure>\n<p>"
      << (e.image("frames").empty() ? Html()
                                    : link(e.image("frames"), "frames.csv") << " &middot; ")
      << link(manifest_rel, "sequence.json") << "</p></section></details>\n";
  }
  if (points.empty()) return {};
  const std::string plots_rel = "runs/" + report.context.run_id + "/plots";
  fs::create_directories(out / plots_rel);
  const Html overlay = sequence_overlay_charts(out_dir, plots_rel, points, charts);
  if (!charts.empty()) render_plots_on_every_core(charts);
  return Html("<section class=\"sequences\" id=\"sequences\"><h2>Sequences (AO over time)</h2>\n")
         << sequence_summary_table(points) << overlay
         << "<p>Each sequence point below (CONTRACT &sect;10; click to unfold): its sequence keys, "
            "a strip of frames that opens the viewer over every kept frame, a video of the "
            "estimate beside the reference, its flicker and lag maps, and rmse_excess by frame "
            "and by frames since disocclusion.</p>\n"
         << h << "</section>\n";
}

}  // namespace aoeval
