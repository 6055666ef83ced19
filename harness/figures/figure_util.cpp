#include "harness/figures/figure_util.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "base/summary.h"
#include "drawing/error_maps.h"
#include "estimators/registry.h"
#include "scenes/instances.h"

namespace aoeval::figures {

namespace IBA = OIIO::ImageBufAlgo;

const EstimatorInfo* lookup_estimator(const std::string& name) {
  for (const auto& e : estimator_registry())
    if (e.name == name) return &e;
  return nullptr;
}

ScoredRun run_scored(FigureContext& ctx, const std::string& estimator, nlohmann::json overrides,
                     const std::string& scene, const std::string& view, int w, int h) {
  EvaluationRequest req;
  req.estimator = &find_estimator(estimator);
  req.overrides = std::move(overrides);
  req.scene = scene;
  req.view = view;
  req.width = w;
  req.height = h;
  ScoredRun r;
  r.row = ctx.session->evaluate(req);
  r.estimate = ctx.session->last_estimate();
  r.width = r.row.width;
  r.height = r.row.height;
  return r;
}

std::pair<int, int> view_size(FigureContext& ctx, const std::string& scene, const std::string& view,
                              int long_side) {
  const View& v = ctx.session->scene(scene).scene.view(view);
  const double aspect = static_cast<double>(v.width) / v.height;
  if (aspect >= 1.0)
    return {long_side, std::max(8, static_cast<int>(std::lround(long_side / aspect)))};
  return {std::max(8, static_cast<int>(std::lround(long_side * aspect))), long_side};
}

const ReferenceImage& reference_of(FigureContext& ctx, const std::string& scene,
                                   const std::string& view, int w, int h,
                                   const AoDefinition& definition) {
  const View& v = ctx.session->scene(scene).scene.view(view);
  return ctx.session->reference(scene, v, w, h, definition);
}

std::vector<uint8_t> compared_mask(FigureContext& ctx, const std::string& scene,
                                   const std::string& view, int w, int h,
                                   const AoDefinition& definition, int only_role) {
  const auto& data = ctx.session->scene(scene);
  const View& v = data.scene.view(view);
  const GBuffer& g = ctx.session->gbuffer(scene, v, w, h);
  const ReferenceImage& ref = ctx.session->reference(scene, v, w, h, definition);
  std::vector<uint8_t> mask(g.pixel_count(), 0);
  const PlacementIds ids(data.scene);  // G-buffer ids are placements (scenes/instances.h)
  for (size_t k = 0; k < mask.size(); ++k) {
    if (!g.covered(k) || !ref.covered(k)) continue;
    if (only_role >= 0) {
      const int id = static_cast<int>(g.object_id[k]);
      const size_t object = id < 0 ? ids.first.size() : ids.object_of(static_cast<size_t>(id));
      if (object >= data.scene.objects.size() ||
          static_cast<int>(data.scene.objects[object].role) != only_role)
        continue;
    }
    mask[k] = 1;
  }
  return mask;
}

Metrics score_against(FigureContext& ctx, const std::string& scene, const std::string& view, int w,
                      int h, const AoDefinition& definition, const std::vector<float>& estimate,
                      const std::vector<uint8_t>& mask) {
  const ReferenceImage& ref = reference_of(ctx, scene, view, w, h, definition);
  return compare_images({w, h, ref.ao.data()}, {w, h, estimate.data()}, mask, ref.stderr_ao);
}

TimedRun time_estimator(FigureContext& ctx, const std::string& estimator,
                        const nlohmann::json& overrides, const std::string& scene,
                        const std::string& view, int w, int h, int warmup, int repetitions) {
  using clock = std::chrono::steady_clock;
  const EstimatorInfo& e = find_estimator(estimator);
  const ParamSet params = resolve_params(e.name, e.params, overrides, "figure " + e.name);
  const auto& data = ctx.session->scene(scene);
  const GBuffer& g = ctx.session->gbuffer(scene, data.scene.view(view), w, h);
  const EstimateContext in{data.scene, *data.embree, g};
  auto est = e.create(params);
  est->prepare(in);
  for (int i = 0; i < warmup; ++i) est->run(in);
  std::vector<double> times, ao_times;
  std::map<std::string, std::vector<double>> passes;
  for (int i = 0; i < std::max(1, repetitions); ++i) {
    const auto t0 = clock::now();
    const EstimateResult r = est->run(in);
    const double wall = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    const auto total = r.pass_ms.find("total_ms");
    times.push_back(total != r.pass_ms.end() ? total->second : wall);
    const auto geometry = r.pass_ms.find("geometry_ms");
    ao_times.push_back(times.back() - (geometry != r.pass_ms.end() ? geometry->second : 0.0));
    for (const auto& [pass, ms] : r.pass_ms) passes[pass].push_back(ms);
  }
  TimedRun t;
  t.median_ms = median(times);
  t.ao_median_ms = median(ao_times);
  t.min_ms = *std::min_element(times.begin(), times.end());
  t.max_ms = *std::max_element(times.begin(), times.end());
  for (auto& [pass, values] : passes) t.pass_ms[pass] = median(values);
  t.pixels = g.pixel_count();
  return t;
}

double masked_mean(const std::vector<float>& v, const std::vector<uint8_t>& mask) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < v.size(); ++k)
    if (mask.empty() || mask[k]) sum += v[k], ++n;
  return n ? sum / static_cast<double>(n) : std::nan("");
}

double pearson(const std::vector<float>& a, const std::vector<float>& b,
               const std::vector<uint8_t>& mask) {
  const double ma = masked_mean(a, mask), mb = masked_mean(b, mask);
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    if (!mask.empty() && !mask[k]) continue;
    const double da = a[k] - ma, db = b[k] - mb;
    sab += da * db, saa += da * da, sbb += db * db;
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

BlockScore block_score(int w, int h, const std::vector<float>& ref, const std::vector<float>& est,
                       const std::vector<uint8_t>& mask, int block) {
  std::vector<float> a, b;
  for (int by = 0; by + block <= h; by += block)
    for (int bx = 0; bx + block <= w; bx += block) {
      double sa = 0.0, sb = 0.0;
      int n = 0;
      for (int j = by; j < by + block; ++j)
        for (int i = bx; i < bx + block; ++i) {
          const size_t k = static_cast<size_t>(j) * w + i;
          if (mask[k]) sa += ref[k], sb += est[k], ++n;
        }
      if (2 * n < block * block) continue;
      a.push_back(static_cast<float>(sa / n));
      b.push_back(static_cast<float>(sb / n));
    }
  BlockScore s;
  s.blocks = a.size();
  if (a.empty()) return s;
  double se = 0.0;
  for (size_t k = 0; k < a.size(); ++k) se += (a[k] - b[k]) * (a[k] - b[k]);
  s.rmse = std::sqrt(se / static_cast<double>(a.size()));
  s.pearson = pearson(a, b, {});
  return s;
}

MeanSe mean_se(const std::vector<double>& v) {
  MeanSe m;
  if (v.empty()) return m;
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(v.size());
  if (v.size() < 2) return m;
  double ss = 0.0;
  for (double x : v) ss += (x - m.mean) * (x - m.mean);
  m.se = std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
  return m;
}

PlotSeries make_series(const std::string& label, const std::string& kind) {
  PlotSeries s;
  s.label = label;
  s.kind = kind;
  return s;
}

namespace {
constexpr float kCanvasGrey = 0.10f;  // the error maps' canvas
constexpr float kTextGrey = 0.92f;
}  // namespace

OIIO::ImageBuf text_panel(int w, int h, const std::string& text) {
  OIIO::ImageBuf panel(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  IBA::fill(panel, {kCanvasGrey, kCanvasGrey, kCanvasGrey});
  const float c[3] = {kTextGrey, kTextGrey, kTextGrey};
  IBA::render_text(panel, w / 2, h / 2, text, text_size_px(h), kFontPath, c,
                   IBA::TextAlignX::Center, IBA::TextAlignY::Center);
  return panel;
}

OIIO::ImageBuf panel_grid(const std::vector<std::vector<OIIO::ImageBuf>>& rows,
                          const std::string& title) {
  size_t cols = 0;
  for (const auto& r : rows) cols = std::max(cols, r.size());
  std::vector<int> col_w(cols, 0), row_h(rows.size(), 0);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < rows[r].size(); ++c) {
      if (!rows[r][c].initialized()) continue;
      col_w[c] = std::max(col_w[c], rows[r][c].spec().width);
      row_h[r] = std::max(row_h[r], rows[r][c].spec().height);
    }
  const int gap = 6;
  int width = gap, height = gap;
  for (int w : col_w) width += w + gap;
  for (int h : row_h) height += h + gap;
  const int fs = std::max(14, width / 70);
  const int title_h = title.empty() ? 0 : fs * 2;
  height += title_h;
  OIIO::ImageBuf canvas(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
  IBA::fill(canvas, {kCanvasGrey, kCanvasGrey, kCanvasGrey});
  if (!title.empty()) {
    const float c[3] = {kTextGrey, kTextGrey, kTextGrey};
    IBA::render_text(canvas, gap, title_h - fs / 2, title, fs, kFontPath, c);
  }
  int y = gap + title_h;
  for (size_t r = 0; r < rows.size(); ++r) {
    int x = gap;
    for (size_t c = 0; c < cols; ++c) {
      if (c < rows[r].size() && rows[r][c].initialized())
        IBA::paste(canvas, x, y, 0, 0, rows[r][c]);
      x += col_w[c] + gap;
    }
    y += row_h[r] + gap;
  }
  return canvas;
}

}  // namespace aoeval::figures
