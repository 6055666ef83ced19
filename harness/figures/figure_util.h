// Shared helpers of the figure functions: running an estimator through the EvaluationSession and
// keeping its estimate, scoring an estimate against any reference under any mask, timing an
// estimator without a reference (throughput tables), small statistics, and image grids built from
// the error-map panels (harness/error_maps.h) with OIIO.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/summary.h"  // median
#include "drawing/plot.h"
#include "harness/figures/figure.h"
#include "harness/scoring/metrics.h"

namespace aoeval::figures {

// The registered estimator, or nullptr when this build does not have it (e.g. hbao-split without
// Vulkan support): figures then say so in their notes instead of failing.
const EstimatorInfo* lookup_estimator(const std::string& name);

struct ScoredRun {
  ResultRow row;                // metrics against the matched reference and true AO, timings
  std::vector<float> estimate;  // per pixel
  int width = 0, height = 0;
};
// session->evaluate() of `estimator` with `overrides`, keeping the estimate. Throws what evaluate
// throws (EstimatorUnavailable when the backend is missing).
ScoredRun run_scored(FigureContext& ctx, const std::string& estimator, nlohmann::json overrides,
                     const std::string& scene, const std::string& view, int w, int h);

// The view's own aspect ratio with its longer side `long_side` pixels (at least 8 on the shorter).
std::pair<int, int> view_size(FigureContext& ctx, const std::string& scene, const std::string& view,
                              int long_side);

// Pixels covered in the G-buffer and the reference; with `only_role` >= 0 further restricted to
// pixels whose object has that Role (e.g. trees).
std::vector<uint8_t> compared_mask(FigureContext& ctx, const std::string& scene,
                                   const std::string& view, int w, int h,
                                   const AoDefinition& definition, int only_role = -1);
// Metrics of `estimate` against the reference of `definition` (same scene, view, size) under
// `mask`; the reference's stderr enters rmse_excess.
Metrics score_against(FigureContext& ctx, const std::string& scene, const std::string& view, int w,
                      int h, const AoDefinition& definition, const std::vector<float>& estimate,
                      const std::vector<uint8_t>& mask);
const ReferenceImage& reference_of(FigureContext& ctx, const std::string& scene,
                                   const std::string& view, int w, int h,
                                   const AoDefinition& definition);

struct TimedRun {
  double median_ms = 0.0, min_ms = 0.0, max_ms = 0.0;
  std::map<std::string, double> pass_ms;  // median per pass over the repetitions
  // Median over the repetitions of the time less the "geometry" pass (the raster G-buffer that
  // gtao, hbao-split and raymarch-ssao draw every frame; plug-ins get the G-buffer ready-made):
  // the AO passes' own time. Equals median_ms for an estimator without that pass.
  double ao_median_ms = 0.0;
  size_t pixels = 0;
  double mpixel_per_s() const { return median_ms > 0 ? pixels / (median_ms * 1e3) : 0.0; }
};
// Times one estimator like `aoeval bench estimators` does (prepare, warm-up runs, timed runs; the
// estimator's own "total_ms" replaces wall time when it reports one), with no reference: for
// tables of throughput and pass times at resolutions where a reference would cost minutes.
TimedRun time_estimator(FigureContext& ctx, const std::string& estimator,
                        const nlohmann::json& overrides, const std::string& scene,
                        const std::string& view, int w, int h, int warmup, int repetitions);

double masked_mean(const std::vector<float>& v, const std::vector<uint8_t>& mask);
// Pearson correlation of a and b over the mask; 0 when either is constant there.
double pearson(const std::vector<float>& a, const std::vector<float>& b,
               const std::vector<uint8_t>& mask);
// The images' appearance at a coarser scale: both averaged over block x block pixel tiles (the
// mask's pixels only; tiles at least half covered), then the RMSE and Pearson r of the tile means.
// Stands in for the paper figures' antialiasing and viewing distance, where a pixel covers many
// leaves.
struct BlockScore {
  double rmse = 0.0, pearson = 0.0;
  size_t blocks = 0;
};
BlockScore block_score(int w, int h, const std::vector<float>& ref, const std::vector<float>& est,
                       const std::vector<uint8_t>& mask, int block);

// Mean and standard error of the mean.
struct MeanSe {
  double mean = 0.0, se = 0.0;
};
MeanSe mean_se(const std::vector<double>& v);

// A plot series with a label and a kind ("line", "bar", ...), its arrays empty.
PlotSeries make_series(const std::string& label, const std::string& kind = "line");

// Panels (8-bit RGB, as error_maps.h returns them) laid out in rows on a dark canvas, each cell as
// large as the largest panel of its row and column, with `title` drawn above when not empty.
// Missing panels (empty ImageBuf) leave their cell blank.
OIIO::ImageBuf panel_grid(const std::vector<std::vector<OIIO::ImageBuf>>& rows,
                          const std::string& title);
// A blank panel carrying one line of text (e.g. "hbao-split: skipped, no Vulkan device").
OIIO::ImageBuf text_panel(int w, int h, const std::string& text);

}  // namespace aoeval::figures
