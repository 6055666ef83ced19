// Pharr and Green 2004, GPU Gems ch. 17 "Ambient Occlusion": Fig. 17-3, a model on a ground plane
// shaded with per-vertex accessibility (Listing 17-1: rays at each triangle centre, averaged to
// the vertices, interpolated per pixel, §17.2), against the per-pixel ray-traced accessibility.
#include <algorithm>
#include <cmath>

#include "drawing/error_maps.h"
#include "harness/figures/figure_util.h"
#include "scenes/exr_io.h"

namespace aoeval::figures {

namespace {

const AoDefinition kAccessibility{Weighting::uniform};  // §17.2: the unoccluded fraction

// Mean estimate over the mask pixels whose reference lies in the lowest (or highest) decile of
// the reference over the mask: how dark the baked map draws what the reference calls darkest.
double decile_mean(const std::vector<float>& ref, const std::vector<float>& est,
                   const std::vector<uint8_t>& mask, bool lowest) {
  std::vector<float> values;
  for (size_t k = 0; k < mask.size(); ++k)
    if (mask[k]) values.push_back(ref[k]);
  if (values.size() < 10) return std::nan("");
  std::sort(values.begin(), values.end());
  const float cut = lowest ? values[values.size() / 10] : values[values.size() * 9 / 10];
  double sum = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < mask.size(); ++k)
    if (mask[k] && (lowest ? ref[k] <= cut : ref[k] >= cut)) sum += est[k], ++n;
  return n ? sum / static_cast<double>(n) : std::nan("");
}

FigureResult fig17_3(FigureContext& ctx) {
  const std::string scene = "elephant", view = "main";
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(240, 48));
  const int rays = ctx.pick(128, 32);
  const std::vector<int> levels = ctx.quick ? std::vector<int>{0, 1} : std::vector<int>{0, 2};
  const ReferenceImage& ref = reference_of(ctx, scene, view, w, h, kAccessibility);
  const auto all = compared_mask(ctx, scene, view, w, h, kAccessibility);
  const auto model =
      compared_mask(ctx, scene, view, w, h, kAccessibility, static_cast<int>(Role::solid));
  const auto ground =
      compared_mask(ctx, scene, view, w, h, kAccessibility, static_cast<int>(Role::ground));
  FigureResult r;
  r.table.columns = {
      "subdivide",    "rays",          "width",       "height",        "rmse",
      "model_rmse",   "model_pearson", "ground_rmse", "ground_shadow", "ref_ground_shadow",
      "precompute_ms"};
  std::vector<OIIO::ImageBuf> top = {ao_image(w, h, ref.ao.data(), all, "per-pixel reference")},
                              bottom = {OIIO::ImageBuf()};
  std::vector<double> model_r, shadow;
  const double ref_shadow =
      decile_mean(ref.ao, ref.ao, ground, false) - decile_mean(ref.ao, ref.ao, ground, true);
  for (int level : levels) {
    const ScoredRun run =
        run_scored(ctx, "vertex-baked", {{"rays", rays}, {"subdivide", level}}, scene, view, w, h);
    const Metrics ma = score_against(ctx, scene, view, w, h, kAccessibility, run.estimate, all);
    const Metrics mm = score_against(ctx, scene, view, w, h, kAccessibility, run.estimate, model);
    const Metrics mg = score_against(ctx, scene, view, w, h, kAccessibility, run.estimate, ground);
    model_r.push_back(pearson(ref.ao, run.estimate, model));
    // The soft shadow under the model: open ground minus the ground the reference calls darkest.
    shadow.push_back(decile_mean(ref.ao, run.estimate, ground, false) -
                     decile_mean(ref.ao, run.estimate, ground, true));
    r.table.add({std::to_string(level), std::to_string(rays), std::to_string(w), std::to_string(h),
                 fmt(ma.rmse), fmt(mm.rmse), fmt(model_r.back()), fmt(mg.rmse), fmt(shadow.back()),
                 fmt(ref_shadow), fmt(run.row.precompute_ms)});
    top.push_back(
        ao_image(w, h, run.estimate.data(), all, "per-vertex, subdivide " + std::to_string(level)));
    bottom.push_back(abs_error_map(w, h, ref.ao.data(), run.estimate.data(), all, 0.5f));
  }
  write_image(ctx.path("gpugems-fig17-3.png"),
              panel_grid({top, bottom}, "GPU Gems ch. 17 Fig. 17-3: per-vertex accessibility"));
  r.images = {"gpugems-fig17-3.png"};
  r.checks.push_back(
      {"on the model, per-vertex accessibility follows the per-pixel reference: "
       "Pearson r >= 0.8 at the finest subdivision ('crevices ... darker than "
       "exposed regions')",
       model_r.back() >= 0.8, "r = " + fmt(model_r.back(), 3)});
  r.checks.push_back(
      {"the soft shadow on the ground plane: the baked map's open-ground minus "
       "shadowed-ground accessibility >= half the reference's, at the finest "
       "subdivision",
       shadow.back() >= 0.5 * ref_shadow,
       "baked " + fmt(shadow.back(), 3) + " (subdivide 0: " + fmt(shadow.front(), 3) +
           "), reference " + fmt(ref_shadow, 3)});
  r.measured = "vertex-baked (" + std::to_string(rays) +
               " rays per triangle centre and side; the chapter used 512) on elephant/main at " +
               std::to_string(w) + "x" + std::to_string(h) + ", subdivide levels " +
               std::to_string(levels.front()) + " and " + std::to_string(levels.back()) +
               ", against the uniform-weighted per-pixel reference; shadow contrast = mean over "
               "ground pixels in the reference's brightest decile minus its darkest decile.";
  r.notes.push_back(
      "the floor is one quad (2 triangles): without subdivision its four corner "
      "vertices cannot carry a shadow, which is why §17.2 assumes a finely "
      "tessellated model.");
  return r;
}

}  // namespace

std::vector<Figure> gpugems_figures() {
  return {
      {"gpugems-fig17-3", "Pharr and Green 2004, GPU Gems ch. 17, Fig. 17-3",
       "Shading a model on a plane with per-vertex accessibility (rays at triangle centres, "
       "averaged to vertices, §17.2): crevices under the legs and the stomach are darker than "
       "exposed regions, and there is a very soft shadow beneath the creature on the ground "
       "plane.",
       fig17_3},
  };
}

}  // namespace aoeval::figures
