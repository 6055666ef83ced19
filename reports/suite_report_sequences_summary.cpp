#include "reports/suite_report_sequences_summary.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>

#include "base/errors.h"
#include "drawing/error_maps.h"
#include "reports/suite_report_leaderboard.h"
#include "reports/suite_report_mosaics.h"
#include "reports/viewer.h"
#include "scenes/exr_io.h"

namespace aoeval {

namespace fs = std::filesystem;

namespace {

std::string view_label(const ResultRow& r) {
  return r.scene + "/" + r.view + " " + std::to_string(r.width) + "x" + std::to_string(r.height);
}

std::string point_label(const ResultRow& r) {
  const std::string params = params_of(r);
  return r.estimator + (params == "defaults" ? "" : " " + params);
}

double key_of(const nlohmann::json& metrics, const std::string& key) {
  const auto it = metrics.find(key);
  return it != metrics.end() && it->is_number() ? it->get<double>() : std::nan("");
}

// A cell the table sorts by: its number in data-v ("" when it has none: sorted last).
Html cell(double v) {
  if (!std::isfinite(v)) return Html("<td data-v=\"\">&ndash;</td>");
  return Html("<td data-v=\"") << number(v, "%.9g") << "\">" << number(v) << "</td>";
}

// The points in the table's order: scene views in order of appearance, within each by true score.
std::vector<const SequencePoint*> ranked(const std::vector<SequencePoint>& points) {
  std::map<std::string, size_t> views;
  for (const auto& p : points) views.emplace(view_label(*p.row), views.size());
  std::vector<const SequencePoint*> out;
  for (const auto& p : points) out.push_back(&p);
  std::stable_sort(out.begin(), out.end(), [&](const SequencePoint* a, const SequencePoint* b) {
    const size_t va = views[view_label(*a->row)], vb = views[view_label(*b->row)];
    if (va != vb) return va < vb;
    const double x = true_score(*a->row), y = true_score(*b->row);
    return !std::isnan(x) && (std::isnan(y) || x < y);
  });
  return out;
}

// One map through inferno, 0..scale; uncompared pixels grey, as the error maps draw them.
OIIO::ImageBuf inferno_panel(int w, int h, const std::vector<float>& values,
                             const std::vector<uint8_t>& mask, float scale) {
  static const std::vector<std::array<uint8_t, 3>> table = colour_table(ErrorMapKind::abs, 256);
  const auto grey = static_cast<uint8_t>(std::lround(kUncomparedGrey * 255.0f));
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (size_t p = 0; p < values.size(); ++p) {
    std::array<uint8_t, 3> c = {grey, grey, grey};
    if (mask[p]) {
      const float t = std::clamp(values[p] / scale, 0.0f, 1.0f);
      c = table[static_cast<size_t>(std::lround(t * 255.0f))];
    }
    std::copy(c.begin(), c.end(), rgb.begin() + 3 * p);
  }
  OIIO::ImageBuf out(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  out.set_pixels(out.roi(), OIIO::TypeDesc::UINT8, rgb.data());
  return out;
}

}  // namespace

Html sequence_summary_table(const std::vector<SequencePoint>& points) {
  if (points.empty()) return {};
  Html h;
  h << "<p>Every sequence point, ranked within its scene view on one truth: <b>true steady</b> is "
       "steady_rmse_excess (the rms of each frame's rmse_excess over the last half of the "
       "frames) against true AO, the unbounded cosine reference every estimator shares; "
       "<b>matched steady</b> the same against the reference of the definition the estimator "
       "declares (shown, not ranked). Beside them, against true AO: temporal_rmse_excess "
       "(flicker beyond the reference's noise), lag_rmse_excess (error where the truth moved "
       "under a surface that stayed in view), disocclusion_rmse_excess, converge_frames and "
       "settle_frames; ms is the median time per frame. Click a header to sort; an estimator "
       "links to its point's section.</p>\n"
       "<table class=\"sortable sequences-summary\"><thead><tr>"
       "<th class=\"l\" data-sort=\"0\" data-type=\"text\">estimator</th>"
       "<th class=\"l\" data-sort=\"1\" data-type=\"text\">scene view</th>"
       "<th data-sort=\"2\">true steady</th><th data-sort=\"3\">matched steady</th>"
       "<th data-sort=\"4\">temporal_rmse_excess</th><th data-sort=\"5\">lag_rmse_excess</th>"
       "<th data-sort=\"6\">disocclusion_rmse_excess</th><th data-sort=\"7\">converge_frames</th>"
       "<th data-sort=\"8\">settle_frames</th><th data-sort=\"9\">ms</th></tr></thead>\n<tbody>\n";
  for (const SequencePoint* p : ranked(points)) {
    const ResultRow& r = *p->row;
    h << "<tr><td class=\"l\"><a href=\"#sequence-" << attr(slug(r.run_name)) << "\">"
      << text(point_label(r)) << "</a></td><td class=\"l\">" << text(view_label(r)) << "</td>"
      << cell(true_score(r)) << cell(matched_score(r))
      << cell(key_of(r.true_metrics, "temporal_rmse_excess"))
      << cell(key_of(r.true_metrics, "lag_rmse_excess"))
      << cell(key_of(r.true_metrics, "disocclusion_rmse_excess"))
      << cell(key_of(r.true_metrics, "converge_frames"))
      << cell(key_of(r.true_metrics, "settle_frames")) << cell(r.time_ms_median) << "</tr>\n";
  }
  h << "</tbody></table>\n";
  return h;
}

Html sequence_overlay_charts(const std::string& out_dir, const std::string& plots_rel,
                             const std::vector<SequencePoint>& points,
                             std::vector<std::pair<PlotSpec, std::string>>& plots) {
  std::vector<std::string> views;
  std::map<std::string, std::vector<const SequencePoint*>> members;
  for (const SequencePoint* p : ranked(points)) {
    const std::string v = view_label(*p->row);
    if (!members.count(v)) views.push_back(v);
    members[v].push_back(p);
  }
  Html h;
  for (const auto& v : views) {
    PlotSpec spec;
    spec.title = v + ": rmse_excess by frame";
    spec.x_label = "frame";
    bool all_true = true;
    std::vector<fs::path> sources;
    for (const SequencePoint* p : members[v]) {
      const nlohmann::json& m = p->manifest;
      const bool has_true = m.contains("true_rmse_excess_by_frame");
      all_true = all_true && has_true;
      const nlohmann::json& values = has_true ? m["true_rmse_excess_by_frame"]
                                              : m.value("rmse_excess_by_frame", nlohmann::json());
      PlotSeries s;
      s.label = point_label(*p->row) + (has_true ? "" : " (matched)");
      for (size_t k = 0; values.is_array() && k < values.size(); ++k)
        if (values[k].is_number()) {
          s.x.push_back(static_cast<double>(k));
          s.y.push_back(values[k].get<double>());
        }
      spec.series.push_back(std::move(s));
      sources.push_back(fs::path(out_dir) / p->dir / "sequence.json");
    }
    spec.y_label = all_true ? "true rmse_excess (against true AO)" : "rmse_excess";
    spec.width_in = 8.0;
    spec.height_in = 3.8;
    const std::string png = plots_rel + "/sequence_" + file_stem_for(v) + ".png";
    if (!up_to_date(fs::path(out_dir) / png, sources))
      plots.emplace_back(std::move(spec), (fs::path(out_dir) / png).string());
    h << "<figure><img class=\"chart\" src=\"" << url(png) << "\" loading=\"lazy\" alt=\""
      << attr(v) << ": rmse_excess by frame of each estimator\"><figcaption>" << text(v)
      << ": each point's rmse_excess by frame" << (all_true ? Html(" against true AO") : Html(""))
      << ", every estimator of this sequence on one y scale.</figcaption></figure>\n";
  }
  return h;
}

Html sequence_maps_figure(const std::string& out_dir, const SequencePoint& point) {
  const auto it = point.manifest.find("maps");
  if (it == point.manifest.end() || !it->is_string()) return {};
  const std::string maps = it->get<std::string>();
  const fs::path exr = fs::path(out_dir) / maps;
  std::error_code ec;
  if (!fs::exists(exr, ec)) return {};
  const OIIO::ImageBuf image = read_image(exr.string());
  const int w = image.spec().width, h = image.spec().height;
  const size_t n = size_t(w) * h;
  std::vector<float> flicker(n), lag(n), a(n);
  const int fc = channel_index(image, "flicker", exr.string()),
            lc = channel_index(image, "lag", exr.string()),
            ac = channel_index(image, "A", exr.string());
  const auto plane = [&](int c, std::vector<float>& values) {
    OIIO::ROI roi = image.roi();
    roi.chbegin = c;
    roi.chend = c + 1;
    image.get_pixels(roi, OIIO::TypeDesc::FLOAT, values.data());
  };
  plane(fc, flicker);
  plane(lc, lag);
  plane(ac, a);
  std::vector<uint8_t> mask(n);
  for (size_t p = 0; p < n; ++p) mask[p] = a[p] > 0.5f;
  const std::vector<float> zero(n, 0.0f);
  const float flicker_scale = nice_ceiling(abs_error_p99(w, h, zero.data(), flicker.data(), mask));
  const float lag_scale = nice_ceiling(abs_error_p99(w, h, zero.data(), lag.data(), mask));
  const std::string png = (fs::path(point.dir) / "maps.png").string();
  if (!up_to_date(fs::path(out_dir) / png, {exr})) {
    const OIIO::ImageBuf left = inferno_panel(w, h, flicker, mask, flicker_scale),
                         right = inferno_panel(w, h, lag, mask, lag_scale);
    constexpr int kGap = 4;
    OIIO::ImageBuf both(OIIO::ImageSpec(2 * w + kGap, h, 3, OIIO::TypeDesc::UINT8));
    OIIO::ImageBufAlgo::fill(both, {0.12f, 0.12f, 0.12f});
    OIIO::ImageBufAlgo::paste(both, 0, 0, 0, 0, left);
    OIIO::ImageBufAlgo::paste(both, w + kGap, 0, 0, 0, right);
    write_image((fs::path(out_dir) / png).string(), both);
  }
  ViewerSpec spec;
  spec.kind = "maps";
  spec.a = write_viewer_data(out_dir, {maps}, {"flicker", "lag"});
  const std::string& name = point.row->run_name;
  return Html("<figure class=\"maps\">")
         << viewer_html(spec, Html("<img class=\"mosaic maps\" src=\"")
                                  << url(png) << "\" loading=\"lazy\" alt=\""
                                  << attr(name + ": flicker and lag maps") << "\">")
         << "<figcaption>Where it flickers and lags, per pixel of the image over the frames "
            "(against the matched reference). Left, <b>flicker</b>: the rms of d, the frame-to-"
            "frame change of the error along the motion (temporal_rmse's terms), inferno 0.."
         << number(flicker_scale)
         << ". Right, <b>lag</b>: the rms excess error over the frames where the truth moved "
            "under a surface that stayed in view (lag_rmse_excess's pixels: a history's trail), "
            "inferno 0.."
         << number(lag_scale)
         << ", 0 where the truth never moved. Grey: never compared in two successive frames. "
            "The viewer probes both values (<a href=\""
         << url(maps) << "\">maps.exr</a>).</figcaption></figure>\n";
}

}  // namespace aoeval
