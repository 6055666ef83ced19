// Pharr and Green 2004, GPU Gems ch. 17 "Ambient Occlusion": Fig. 17-3, a model on a ground plane
// shaded with per-vertex accessibility (Listing 17-1: rays at each triangle centre, averaged to
// the vertices, interpolated per pixel, §17.2), against the per-pixel ray-traced accessibility.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "drawing/error_maps.h"
#include "estimators/registry.h"
#include "harness/figures/figure_checks.h"
#include "harness/figures/figure_util.h"
#include "harness/figures/figures_gpugems.h"
#include "scenes/corpus.h"
#include "scenes/exr_io.h"

namespace aoeval::figures {

namespace fs = std::filesystem;

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

}  // namespace

PlainEstimate estimate_on(FigureContext& ctx, const std::string& estimator,
                          const nlohmann::json& overrides, const std::string& scene,
                          const GBuffer& g) {
  const EstimatorInfo& e = find_estimator(estimator);
  auto est = e.create(resolve_params(e.name, e.params, overrides, "figure"));
  const auto& data = ctx.session->scene(scene);
  const EstimateContext context{data.scene, *data.embree, g};
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  est->prepare(context);
  const auto t1 = clock::now();
  PlainEstimate out;
  out.ao = est->run(context).ao;
  out.precompute_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  out.frame_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
  return out;
}

std::string floor_variant(FigureContext& ctx, const std::string& scene, int subdivisions) {
  const fs::path source = resolve_scene_path(scene);
  nlohmann::json j;
  {
    std::ifstream in(source);
    j = nlohmann::json::parse(in);
  }
  for (auto& o : j.at("objects")) {
    if (o.value("role", "") == "ground" && o.value("generator", "") == "plane")
      o["params"]["subdivisions"] = subdivisions;
    // Mesh paths are relative to the scene file (CONTRACT §4): keep them pointing at the corpus.
    if (o.contains("mesh")) {
      const std::string m = o["mesh"].get<std::string>();
      if (m.rfind("cache:", 0) != 0 && fs::path(m).is_relative())
        o["mesh"] = (source.parent_path() / m).string();
    }
  }
  const fs::path dir = fs::path(ctx.out_dir) / "scenes";
  fs::create_directories(dir);
  const fs::path out = dir / (scene + "-floor" + std::to_string(subdivisions) + ".json");
  write_text(out.string(), j.dump(2) + "\n");
  return out.string();
}

namespace {

// One row of fig17_3: an estimate's scores and its panels.
struct Fig17Row {
  std::string estimator, mode;
  int floor = 1, samples = 0;
  size_t floor_triangles = 0;
  double rmse = 0, model_rmse = 0, model_r = 0, ground_rmse = 0, shadow = 0, precompute_ms = 0;
};

FigureResult fig17_3(FigureContext& ctx) {
  const std::string scene = "elephant", view = "main";
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(240, 48));
  const int rays = ctx.pick(128, 32);
  // Equal counts: vertex-baked traces `rays` per side over its hemisphere; shadowmap-ao's lights
  // cover the whole sphere, so 2 x rays of them put `rays` above each side on average.
  const int lights = 2 * rays, map = ctx.pick(512, 128);
  // The floor's tessellation (the plane generator's `subdivisions`, a scene parameter): the bake
  // stores values at vertices only, so one quad cannot carry a shadow smaller than itself.
  const std::vector<int> floors =
      ctx.quick ? std::vector<int>{1, 16} : std::vector<int>{1, 4, 16, 64};
  const View& v = ctx.session->scene(scene).scene.view(view);
  const GBuffer& g = ctx.session->gbuffer(scene, v, w, h);
  const ReferenceImage& ref = reference_of(ctx, scene, view, w, h, kAccessibility);
  const auto all = compared_mask(ctx, scene, view, w, h, kAccessibility);
  const auto model =
      compared_mask(ctx, scene, view, w, h, kAccessibility, static_cast<int>(Role::solid));
  const auto ground =
      compared_mask(ctx, scene, view, w, h, kAccessibility, static_cast<int>(Role::ground));
  FigureResult r;
  r.table.columns = {"estimator",
                     "mode",
                     "floor_subdivisions",
                     "floor_triangles",
                     "rays_or_lights",
                     "width",
                     "height",
                     "rmse",
                     "model_rmse",
                     "model_pearson",
                     "ground_rmse",
                     "ground_shadow",
                     "ref_ground_shadow",
                     "precompute_ms"};
  const double ref_shadow =
      decile_mean(ref.ao, ref.ao, ground, false) - decile_mean(ref.ao, ref.ao, ground, true);
  std::vector<OIIO::ImageBuf> ref_row = {ao_image(w, h, ref.ao.data(), all, "per-pixel reference")};
  std::vector<OIIO::ImageBuf> vb_row, vb_err, sm_row, sm_err;
  std::vector<Fig17Row> rows;
  std::string skipped;
  auto score = [&](const std::string& estimator, const std::string& mode, int floor, int samples,
                   const std::string& scene_file, const nlohmann::json& overrides,
                   std::vector<OIIO::ImageBuf>& images, std::vector<OIIO::ImageBuf>& errors) {
    PlainEstimate e;
    try {
      e = estimate_on(ctx, estimator, overrides, scene_file, g);
    } catch (const EstimatorUnavailable& x) {
      skipped = estimator + ": skipped, " + x.what();
      return;
    }
    Fig17Row row{estimator, mode, floor, samples};
    for (const auto& o : ctx.session->scene(scene_file).scene.objects)
      if (o.role == Role::ground) row.floor_triangles += o.mesh.triangle_count();
    row.rmse = score_against(ctx, scene, view, w, h, kAccessibility, e.ao, all).rmse;
    row.model_rmse = score_against(ctx, scene, view, w, h, kAccessibility, e.ao, model).rmse;
    row.ground_rmse = score_against(ctx, scene, view, w, h, kAccessibility, e.ao, ground).rmse;
    row.model_r = pearson(ref.ao, e.ao, model);
    // The soft shadow under the model: open ground minus the ground the reference calls darkest.
    row.shadow = decile_mean(ref.ao, e.ao, ground, false) - decile_mean(ref.ao, e.ao, ground, true);
    row.precompute_ms = e.precompute_ms;
    r.table.add({estimator, mode, std::to_string(floor), std::to_string(row.floor_triangles),
                 std::to_string(samples), std::to_string(w), std::to_string(h), fmt(row.rmse),
                 fmt(row.model_rmse), fmt(row.model_r), fmt(row.ground_rmse), fmt(row.shadow),
                 fmt(ref_shadow), fmt(row.precompute_ms)});
    images.push_back(ao_image(w, h, e.ao.data(), all,
                              estimator + " " + mode + ", floor " + std::to_string(floor)));
    errors.push_back(abs_error_map(w, h, ref.ao.data(), e.ao.data(), all, 0.5f));
    rows.push_back(row);
  };
  // §17.3 as the chapter runs it: the accumulated image, per pixel (the floor's tessellation does
  // not matter there).
  score("shadowmap-ao", "pixel", 1, lights, scene,
        {{"lights", lights}, {"resolution", map}, {"mode", "pixel"}}, sm_row, sm_err);
  for (int floor : floors) {
    const std::string file = floor_variant(ctx, scene, floor);
    score("vertex-baked", "vertex", floor, rays, file, {{"rays", rays}}, vb_row, vb_err);
    score("shadowmap-ao", "vertex", floor, lights, file,
          {{"lights", lights}, {"resolution", map}, {"mode", "vertex"}}, sm_row, sm_err);
  }
  ref_row.insert(ref_row.end(), vb_row.begin(), vb_row.end());
  vb_err.insert(vb_err.begin(), OIIO::ImageBuf());
  std::vector<std::vector<OIIO::ImageBuf>> grid = {ref_row, vb_err};
  if (!sm_row.empty()) grid.insert(grid.end(), {sm_row, sm_err});
  write_image(ctx.path("gpugems-fig17-3.png"),
              panel_grid(grid,
                         "GPU Gems ch. 17 Fig. 17-3: per-vertex accessibility against the "
                         "floor's tessellation"));
  r.images = {"gpugems-fig17-3.png"};

  auto find = [&](const std::string& estimator, const std::string& mode, int floor) {
    for (const Fig17Row& row : rows)
      if (row.estimator == estimator && row.mode == mode && row.floor == floor) return &row;
    return static_cast<const Fig17Row*>(nullptr);
  };
  const Fig17Row* coarse = find("vertex-baked", "vertex", floors.front());
  const Fig17Row* fine = find("vertex-baked", "vertex", floors.back());
  std::string contrast;  // the shadow contrast against the tessellation
  for (int floor : floors)
    if (const Fig17Row* row = find("vertex-baked", "vertex", floor))
      contrast += (contrast.empty() ? "" : ", ") + std::to_string(row->floor_triangles) +
                  " floor triangles: " + fmt(row->shadow, 3);
  Fig17Numbers n;
  n.ref_shadow = ref_shadow;
  n.contrast = contrast;
  if (fine) {
    n.have_fine = true;
    n.fine_model_r = fine->model_r;
    n.fine_shadow = fine->shadow;
    n.fine_rmse = fine->rmse;
  }
  if (coarse) {
    n.have_coarse = true;
    n.coarse_shadow = coarse->shadow;
  }
  if (const Fig17Row* sm = find("shadowmap-ao", "vertex", floors.back())) {
    n.have_shadowmap = true;
    n.shadowmap_model_r = sm->model_r;
    n.shadowmap_shadow = sm->shadow;
    n.shadowmap_rmse = sm->rmse;
  }
  r.checks = gpugems_fig17_checks(n);
  r.measured = "vertex-baked (" + std::to_string(rays) +
               " rays per triangle centre and side; the chapter used 512) and shadowmap-ao (" +
               std::to_string(lights) + " uniform lights on the sphere, about " +
               std::to_string(rays) + " above each side, " + std::to_string(map) +
               "² maps; per vertex, and per pixel as §17.3 accumulates it) on elephant/main at " +
               std::to_string(w) + "x" + std::to_string(h) +
               ", the floor (plane generator) at subdivisions " + std::to_string(floors.front()) +
               " to " + std::to_string(floors.back()) +
               " per side, against the uniform-weighted per-pixel reference; shadow contrast = "
               "mean over ground pixels in the reference's brightest decile minus its darkest "
               "decile.";
  r.notes.push_back("shadow contrast against the floor's tessellation (vertex-baked): " + contrast +
                    "; the reference's is " + fmt(ref_shadow, 3) + ".");
  r.notes.push_back(
      "the tessellated floors are copies of scenes/corpus/elephant.json with the floor's "
      "`subdivisions` set (written under scenes/ beside this figure); their surfaces are "
      "elephant's, so elephant's G-buffer and reference score them.");
  if (!skipped.empty()) r.notes.push_back(skipped);
  return r;
}

}  // namespace

std::vector<Check> gpugems_fig17_checks(const Fig17Numbers& n) {
  std::vector<Check> c;
  c.push_back(
      {"on the model, per-vertex accessibility follows the per-pixel reference: "
       "Pearson r >= 0.8 ('crevices ... darker than exposed regions')",
       n.have_fine && n.fine_model_r >= 0.8,
       n.have_fine ? "r = " + fmt(n.fine_model_r, 3) : "not run"});
  c.push_back(
      {"the soft shadow on the ground plane: the baked map's open-ground minus "
       "shadowed-ground accessibility >= half the reference's, on the finest floor",
       n.have_fine && n.fine_shadow >= 0.5 * n.ref_shadow,
       "vertex-baked " + n.contrast + "; reference " + fmt(n.ref_shadow, 3)});
  c.push_back(
      {"a finely tessellated floor is what carries it (§17.2 assumes a finely tessellated model): "
       "the finest floor's contrast exceeds the one-quad floor's by at least a quarter of the "
       "reference's",
       n.have_fine && n.have_coarse && n.fine_shadow - n.coarse_shadow >= 0.25 * n.ref_shadow,
       n.have_fine && n.have_coarse ? fmt(n.coarse_shadow, 3) + " -> " + fmt(n.fine_shadow, 3)
                                    : "not run"});
  if (n.have_shadowmap)
    c.push_back(
        {"§17.3's shadow-mapped lights bake the same picture: shadowmap-ao per vertex on the "
         "finest floor has model r >= 0.8 and ground shadow >= half the reference's",
         n.shadowmap_model_r >= 0.8 && n.shadowmap_shadow >= 0.5 * n.ref_shadow,
         "r = " + fmt(n.shadowmap_model_r, 3) + ", shadow " + fmt(n.shadowmap_shadow, 3) +
             " (vertex-baked " + (n.have_fine ? fmt(n.fine_shadow, 3) : "not run") + "), rmse " +
             fmt(n.shadowmap_rmse, 3) + " vs vertex-baked " +
             (n.have_fine ? fmt(n.fine_rmse, 3) : "not run")});
  return c;
}

std::vector<Figure> gpugems_figures() {
  return {
      {"gpugems-fig17-3", "Pharr and Green 2004, GPU Gems ch. 17, Fig. 17-3",
       "Shading a model on a plane with per-vertex accessibility (rays at triangle centres, "
       "averaged to vertices, §17.2): crevices under the legs and the stomach are darker than "
       "exposed regions, and there is a very soft shadow beneath the creature on the ground "
       "plane.",
       fig17_3},
      {"gpugems-lights", "Pharr and Green 2004, GPU Gems ch. 17, §17.3",
       "\"A large number of lights (128 to 1024) is required for good results ... lights "
       "distributed at evenly spaced longitudes and latitudes ... tends to concentrate too many "
       "samples at the poles. Instead, you should use a uniform distribution on the sphere.\"",
       gpugems_lights},
  };
}

}  // namespace aoeval::figures
