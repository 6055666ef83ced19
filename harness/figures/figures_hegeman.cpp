// Hegeman, Premoze, Ashikhmin, Drettakis 2006, "Approximate Ambient Occlusion for Trees" (I3D '06):
// Fig. 2 (truth | eq. 4-6 approximation | difference), Fig. 8 (ellipsoid vs sphere on a poplar),
// Fig. 12 (ours vs Reeves-Blau vs ambient on an ecosystem) and §4's shader throughput (460 / 580 /
// 2300 Mpixel/s on a GeForce 6800 Ultra). The paper's AO is eq. 3's uniform-weighted ambient
// visibility, so every estimate here is scored against the uniform, unbounded reference.
#include <algorithm>
#include <cmath>

#include "drawing/error_maps.h"
#include "drawing/plot.h"
#include "harness/figures/figure_checks.h"
#include "harness/figures/figure_timing.h"
#include "harness/figures/figure_util.h"
#include "harness/figures/figures_gpugems.h"
#include "scenes/exr_io.h"

namespace aoeval::figures {

namespace {

const AoDefinition kUniform{Weighting::uniform};
constexpr int kTreeRole = static_cast<int>(Role::tree);

float common_error_scale(const std::vector<std::pair<const float*, const float*>>& pairs, int w,
                         int h, const std::vector<std::vector<uint8_t>>& masks) {
  float p99 = 0.0f;
  for (size_t i = 0; i < pairs.size(); ++i)
    p99 = std::max(p99, abs_error_p99(w, h, pairs[i].first, pairs[i].second, masks[i]));
  return nice_ceiling(p99);
}

// ---- Fig. 2 ----------------------------------------------------------------------------------

// Tile scores of one estimate (TileScore: the appearance at the paper's antialiased scale).
TileScore tiles(int w, int h, const std::vector<float>& ref, const std::vector<float>& est,
                const std::vector<uint8_t>& mask, int block) {
  const BlockScore b = block_score(w, h, ref, est, mask, block);
  return {b.rmse, b.pearson};
}

// Eq. 6 at its best alpha rho: the alpha_scale (x the derived alpha rho) of least tile RMSE, by a
// grid over 10^-2 .. 10^2 in quarter decades, then golden-section search in log scale on the
// bracket around the grid's best (tile RMSE is smooth and, on these scenes, unimodal in the
// scale; the grid keeps the search from a local dip). The paper picks alpha rho by hand per object
// (§4), so this is the most any user could get from eq. 6.
double best_alpha_scale(FigureContext& ctx, const std::string& scene, const GBuffer& g,
                        const std::vector<float>& ref, const std::vector<uint8_t>& mask,
                        int block) {
  auto cost = [&](double log_scale) {
    const PlainEstimate e =
        estimate_on(ctx, "tree-sphere", {{"alpha_scale", std::pow(10.0, log_scale)}}, scene, g);
    return tiles(g.width, g.height, ref, e.ao, mask, block).rmse;
  };
  double best = 0.0, best_cost = cost(0.0);
  for (double l = -2.0; l <= 2.0 + 1e-9; l += 0.25) {
    const double c = cost(l);
    if (c < best_cost) best = l, best_cost = c;
  }
  const double phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = std::max(-2.0, best - 0.25), b = std::min(2.0, best + 0.25);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int it = 0; it < 12; ++it) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - phi * (b - a), f1 = cost(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + phi * (b - a), f2 = cost(x2);
    }
  }
  const double refined = f1 < f2 ? x1 : x2;
  return std::pow(10.0, std::min(f1, f2) < best_cost ? refined : best);
}

FigureResult fig2(FigureContext& ctx) {
  const std::vector<std::string> scenes = {"sphere-uniform", "sphere-uniform-dense", "tree-apple",
                                           "tree-poplar"};
  const std::string view = "front";
  FigureResult r;
  r.table.columns = {"scene",    "view",     "model",      "alpha_scale",   "width",
                     "height",   "pixels",   "rmse",       "bias",          "pearson",
                     "ref_mean", "est_mean", "block_rmse", "block_pearson", "derived"};
  std::vector<std::vector<OIIO::ImageBuf>> rows;
  Fig2Numbers n;
  n.scenes = scenes;
  std::vector<TileScore> volume_ellipsoid_tiles;  // reported, not checked: not the paper's model
  const int block = ctx.pick(8, 4);
  for (const auto& scene : scenes) {
    const auto [w, h] = view_size(ctx, scene, view, ctx.pick(200, 40));
    const GBuffer& g =
        ctx.session->gbuffer(scene, ctx.session->scene(scene).scene.view(view), w, h);
    const ScoredRun derived =
        run_scored(ctx, "tree-sphere", nlohmann::json::object(), scene, view, w, h);
    const auto mask = compared_mask(ctx, scene, view, w, h, kUniform, kTreeRole);
    const ReferenceImage& ref = reference_of(ctx, scene, view, w, h, kUniform);
    const double scale = best_alpha_scale(ctx, scene, g, ref.ao, mask, block);
    const std::vector<float> best =
        estimate_on(ctx, "tree-sphere", {{"alpha_scale", scale}}, scene, g).ao;
    const std::vector<float> volume =
        estimate_on(ctx, "tree-volume", nlohmann::json::object(), scene, g).ao;
    const std::vector<float> volume_ellipsoid =
        estimate_on(ctx, "tree-volume", {{"proxy", "ellipsoid"}}, scene, g).ao;
    const std::string proxies =
        derived.row.params.value("derived", nlohmann::json::object()).dump();
    auto add = [&](const std::string& model, double alpha_scale, const std::vector<float>& est) {
      const Metrics m = score_against(ctx, scene, view, w, h, kUniform, est, mask);
      const TileScore t = tiles(w, h, ref.ao, est, mask, block);
      r.table.add({scene, view, model, alpha_scale > 0 ? fmt(alpha_scale) : "", std::to_string(w),
                   std::to_string(h), std::to_string(m.pixels), fmt(m.rmse), fmt(m.bias),
                   fmt(pearson(ref.ao, est, mask)), fmt(masked_mean(ref.ao, mask)),
                   fmt(masked_mean(est, mask)), fmt(t.rmse), fmt(t.pearson), proxies});
      return t;
    };
    n.derived.push_back(add("eq6-derived", 1.0, derived.estimate));
    n.best.push_back(add("eq6-best-scale", scale, best));
    n.volume.push_back(add("tree-volume", 0.0, volume));
    volume_ellipsoid_tiles.push_back(add("tree-volume-ellipsoid", 0.0, volume_ellipsoid));
    n.best_scale.push_back(scale);
    const float err =
        nice_ceiling(std::max({abs_error_p99(w, h, ref.ao.data(), best.data(), mask),
                               abs_error_p99(w, h, ref.ao.data(), volume.data(), mask), 0.05f}));
    rows.push_back({ao_image(w, h, ref.ao.data(), mask, scene + ": truth"),
                    ao_image(w, h, derived.estimate.data(), mask, "eq. 6 as derived"),
                    ao_image(w, h, best.data(), mask, "eq. 6 at best scale " + fmt(scale, 2)),
                    ao_image(w, h, volume.data(), mask, "tree-volume"),
                    abs_error_map(w, h, ref.ao.data(), best.data(), mask, err),
                    abs_error_map(w, h, ref.ao.data(), volume.data(), mask, err)});
  }
  write_image(ctx.path("hegeman-fig2.png"),
              panel_grid(rows,
                         "Hegeman et al. 2006 Fig. 2: truth | eq. 6 | eq. 6 at best scale | "
                         "tree-volume | |error| of the last two"));
  r.images = {"hegeman-fig2.png"};
  r.checks = hegeman_fig2_checks(n);
  std::string lines;
  for (size_t i = 0; i < scenes.size(); ++i)
    lines += std::string(i ? "; " : "") + scenes[i] + ": eq. 6 as derived " +
             fmt(n.derived[i].rmse, 3) + " / r " + fmt(n.derived[i].pearson, 2) +
             ", eq. 6 at best scale (x" + fmt(n.best_scale[i], 3) + ") " + fmt(n.best[i].rmse, 3) +
             " / r " + fmt(n.best[i].pearson, 2) + ", tree-volume " + fmt(n.volume[i].rmse, 3) +
             " / r " + fmt(n.volume[i].pearson, 2) + " (ellipsoid proxy " +
             fmt(volume_ellipsoid_tiles[i].rmse, 3) + " / r " +
             fmt(volume_ellipsoid_tiles[i].pearson, 2) + ")";
  r.measured =
      "against the uniform-weighted unbounded reference (eq. 3, " +
      std::to_string(ctx.session->reference_spec().spp) +
      " spp), front views, tree pixels only, three models: tree-sphere's eq. 4-6 with alpha rho "
      "derived from the leaves (3 lambda / (2 pi R^2), exact at the crown's centre), the same at "
      "the alpha_scale of least tile RMSE (a 1-D search per scene: the paper's model at best, as "
      "the paper tunes alpha rho by hand per object), and tree-volume (ours, beyond the paper: "
      "§3's Poisson argument per direction, exp(-lambda chord) averaged over the hemisphere, same "
      "lambda, 4 x 8 directions; also with the ellipsoid proxy, row tree-volume-ellipsoid). Tile "
      "RMSE / tile Pearson r over " +
      std::to_string(block) + "x" + std::to_string(block) + " pixel tiles: " + lines +
      ". Error maps share a scale per row.";
  r.notes.push_back(
      "why eq. 6 fails: it counts every leaf in the cap cut by the tangent plane alike, whatever "
      "its distance, so its exponent grows like the cap *volume* (eq. 4, ~h^2 (3R - h)), while "
      "the Poisson (Beer-Lambert) occlusion of each direction grows with the *path length* "
      "through the crown. Points near the surface facing out come out too bright, facing in far "
      "too dark, and the trend across the crown is reversed; rescaling alpha rho removes the bias "
      "but not that shape. tree-volume keeps §3's argument per direction and follows the truth "
      "where its proxy fits the crown; the poplar's bounding sphere is mostly empty (a tall, "
      "narrow crown), which spreads lambda thin and makes the leaves too bright: its ellipsoid "
      "(Fig. 8's envelope) fits.");
  r.notes.push_back(
      "dropped: the former check 'apple RMSE >= 1.5 x the spheres'' passed only when the apple "
      "was estimated badly; it measured the estimate's failure, not the claim.");
  return r;
}

// ---- Fig. 8 ----------------------------------------------------------------------------------

FigureResult fig8(FigureContext& ctx) {
  const std::string scene = "tree-poplar", view = "front";
  const auto [w, h] = view_size(ctx, scene, view, ctx.pick(240, 48));
  const std::vector<std::string> estimators = {"tree-ellipsoid", "tree-sphere", "tree-shells"};
  const auto mask = compared_mask(ctx, scene, view, w, h, kUniform, kTreeRole);
  const ReferenceImage& ref = reference_of(ctx, scene, view, w, h, kUniform);
  FigureResult r;
  r.table.columns = {"estimator", "scene", "width",   "height",   "pixels",   "rmse",      "mae",
                     "bias",      "ssim",  "pearson", "est_mean", "ref_mean", "block_rmse"};
  std::vector<std::vector<float>> estimates;
  std::vector<double> rmse;
  std::vector<OIIO::ImageBuf> top = {ao_image(w, h, ref.ao.data(), mask, "truth")};
  for (const auto& e : estimators) {
    const ScoredRun run = run_scored(ctx, e, nlohmann::json::object(), scene, view, w, h);
    const Metrics m = score_against(ctx, scene, view, w, h, kUniform, run.estimate, mask);
    const BlockScore b = block_score(w, h, ref.ao, run.estimate, mask, ctx.pick(8, 4));
    rmse.push_back(b.rmse);
    r.table.add({e, scene, std::to_string(w), std::to_string(h), std::to_string(m.pixels),
                 fmt(m.rmse), fmt(m.mae), fmt(m.bias), fmt(m.ssim),
                 fmt(pearson(ref.ao, run.estimate, mask)), fmt(masked_mean(run.estimate, mask)),
                 fmt(masked_mean(ref.ao, mask)), fmt(b.rmse)});
    top.push_back(ao_image(w, h, run.estimate.data(), mask, e));
    estimates.push_back(run.estimate);
  }
  const float scale = common_error_scale({{ref.ao.data(), estimates[0].data()},
                                          {ref.ao.data(), estimates[1].data()},
                                          {ref.ao.data(), estimates[2].data()}},
                                         w, h, {mask, mask, mask});
  std::vector<OIIO::ImageBuf> bottom = {OIIO::ImageBuf()};
  for (const auto& est : estimates)
    bottom.push_back(abs_error_map(w, h, ref.ao.data(), est.data(), mask, scale));
  write_image(
      ctx.path("hegeman-fig8.png"),
      panel_grid({top, bottom}, "Hegeman et al. 2006 Fig. 8: ellipsoid vs sphere (poplar)"));
  r.images = {"hegeman-fig8.png"};
  double diff = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < mask.size(); ++k)
    if (mask[k]) diff += std::abs(estimates[0][k] - estimates[1][k]), ++n;
  diff = n ? diff / static_cast<double>(n) : 0.0;
  r.checks = hegeman_fig8_checks({rmse[0], rmse[1], rmse[2], diff});
  r.measured =
      "tree-ellipsoid, tree-sphere and tree-shells (defaults, alpha rho derived) on "
      "tree-poplar/front at " +
      std::to_string(w) + "x" + std::to_string(h) +
      " against the uniform unbounded reference, tree pixels only; RMSE checks on 8x8-pixel "
      "tile means (block_rmse, as in hegeman-fig2).";
  return r;
}

// ---- Fig. 12 ---------------------------------------------------------------------------------

FigureResult fig12(FigureContext& ctx) {
  const std::string scene = "ecosystem";
  const std::vector<std::string> views = {"overview", "meadow"};
  struct Shader {
    std::string estimator, label;
    nlohmann::json overrides;
  };
  const std::vector<Shader> shaders = {{"tree-sphere", "ours (tree-sphere)", {}},
                                       {"reeves-blau", "Reeves-Blau", {}},
                                       {"constant", "ambient only", {{"value", 1.0}}}};
  FigureResult r;
  r.table.columns = {"view",         "estimator", "width",     "height",
                     "tree_pixels",  "tree_rmse", "tree_bias", "tree_ssim",
                     "tree_pearson", "all_rmse",  "all_pixels"};
  std::vector<std::vector<OIIO::ImageBuf>> rows;
  std::vector<std::vector<double>> tree_rmse(views.size()), tree_r(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    const auto [w, h] = view_size(ctx, scene, views[v], ctx.pick(320, 64));
    const auto trees = compared_mask(ctx, scene, views[v], w, h, kUniform, kTreeRole);
    const auto all = compared_mask(ctx, scene, views[v], w, h, kUniform);
    const ReferenceImage& ref = reference_of(ctx, scene, views[v], w, h, kUniform);
    std::vector<OIIO::ImageBuf> row = {ao_image(w, h, ref.ao.data(), all, views[v] + ": truth")};
    for (const auto& s : shaders) {
      const ScoredRun run = run_scored(ctx, s.estimator, s.overrides, scene, views[v], w, h);
      const Metrics mt = score_against(ctx, scene, views[v], w, h, kUniform, run.estimate, trees);
      const Metrics ma = score_against(ctx, scene, views[v], w, h, kUniform, run.estimate, all);
      const double rho = pearson(ref.ao, run.estimate, trees);
      tree_rmse[v].push_back(mt.rmse);
      tree_r[v].push_back(rho);
      r.table.add({views[v], s.estimator, std::to_string(w), std::to_string(h),
                   std::to_string(mt.pixels), fmt(mt.rmse), fmt(mt.bias), fmt(mt.ssim), fmt(rho),
                   fmt(ma.rmse), std::to_string(ma.pixels)});
      row.push_back(ao_image(w, h, run.estimate.data(), all, s.label));
    }
    rows.push_back(std::move(row));
  }
  write_image(
      ctx.path("hegeman-fig12.png"),
      panel_grid(rows, "Hegeman et al. 2006 Fig. 12: truth | ours | Reeves-Blau | ambient"));
  r.images = {"hegeman-fig12.png"};
  r.checks = hegeman_fig12_checks({views, tree_rmse, tree_r});
  r.measured = "the ecosystem scene (" + std::string("20 objects, 6.3 M triangles") +
               "), views overview and meadow, tree-sphere / reeves-blau (defaults, proxies "
               "derived) / constant 1, all scored against the uniform unbounded reference over "
               "tree pixels (and all pixels in the CSV).";
  return r;
}

// ---- throughput (§4) -------------------------------------------------------------------------

FigureResult throughput(FigureContext& ctx) {
  // §4: NVShaderPerf fragment throughput on a GeForce 6800 Ultra.
  const double paper[3] = {460.0, 580.0, 2300.0};
  const std::string scene = "tree-apple", view = "front";
  const int side = ctx.pick(512, 48);  // the paper's 512x512 single-tree measurement
  // The ambient-only shader is tree-sphere's own pass with the visibility left out
  // (ambient_only): the same per-pixel loop over the G-buffer, the same object rules, a constant
  // term, as the paper's ambient shader is its AO shader without the occlusion.
  const std::vector<Contender> shaders = {
      {"tree-sphere", nlohmann::json::object(), scene, view, side, side},
      {"reeves-blau", nlohmann::json::object(), scene, view, side, side},
      {"tree-sphere", {{"ambient_only", true}}, scene, view, side, side}};
  const std::vector<std::string> labels = {"tree-sphere", "reeves-blau",
                                           "tree-sphere ambient_only"};
  FigureResult r;
  r.table.columns = {"estimator",
                     "scene",
                     "width",
                     "height",
                     "repetitions",
                     "time_ms_median",
                     "time_ms_min",
                     "time_ms_max",
                     "mpixel_per_s",
                     "relative_to_ambient",
                     "paper_mpixel_per_s",
                     "paper_relative_to_ambient"};
  // Interleaved rounds. A frame is about a millisecond, so many are cheap, and 15 left the order's
  // p at 0.005 once on this shared machine (a few rounds hit by a build): 31 a side.
  const int warmup = ctx.pick(3, 1), reps = ctx.pick(31, 9);
  const InterleavedTimes t = time_interleaved(ctx, shaders, warmup, reps);
  std::vector<double> mpix;
  PlotSpec plot;
  plot.title = "Hegeman et al. 2006 §4: throughput relative to ambient only";
  plot.y_label = "Mpixel/s / ambient-only Mpixel/s";
  plot.log_y = true;
  plot.categories = {"ours (tree-sphere)", "Reeves-Blau", "ambient only"};
  PlotSeries ours = make_series("aoeval, CPU", "bar"),
             theirs = make_series("paper, GeForce 6800 Ultra", "bar");
  for (size_t i = 0; i < shaders.size(); ++i) {
    const double med = t.median(i);
    mpix.push_back(med > 0 ? t.pixels[i] / (med * 1e3) : 0.0);
    r.table.add({labels[i], scene, std::to_string(side), std::to_string(side), std::to_string(reps),
                 fmt(med), fmt(*std::min_element(t.ms[i].begin(), t.ms[i].end())),
                 fmt(*std::max_element(t.ms[i].begin(), t.ms[i].end())), fmt(mpix[i]), "",
                 fmt(paper[i]), fmt(paper[i] / paper[2])});
  }
  for (size_t i = 0; i < shaders.size(); ++i) {
    r.table.rows[i][9] = fmt(mpix[i] / mpix[2]);
    ours.x.push_back(static_cast<double>(i));
    ours.y.push_back(mpix[i] / mpix[2]);
    theirs.x.push_back(static_cast<double>(i));
    theirs.y.push_back(paper[i] / paper[2]);
  }
  plot.series = {ours, theirs};
  plot.notes = {"absolute: ours " + fmt(mpix[0], 3) + " / " + fmt(mpix[1], 3) + " / " +
                fmt(mpix[2], 3) + " Mpixel/s; paper 460 / 580 / 2300"};
  render_plot(plot, ctx.path("hegeman-throughput.png"));
  r.images = {"hegeman-throughput.png"};
  r.checks = hegeman_throughput_checks({t.ms[0], t.ms[1], t.ms[2]});
  r.measured = "per-pixel time of each shader on tree-apple/front at " + std::to_string(side) +
               "x" + std::to_string(side) + " (the paper's 512x512 tree), on this CPU; " +
               std::to_string(reps) + " interleaved rounds after " + std::to_string(warmup) +
               " warm-up (every round runs each shader once, in rotating order), decided by the "
               "one-sided Mann-Whitney rank test at alpha 0.01; Mpixel/s from the medians. Only "
               "ratios between shaders can transfer from a 2006 GPU to a CPU.";
  r.notes.push_back(
      "the paper's frame rates (23 / 25 / 31 fps at 512x512 for a 550k-triangle "
      "tree) are geometry-bound and not compared.");
  r.notes.push_back(
      "ambient only = tree-sphere with ambient_only: the same pass over the same G-buffer "
      "(coverage, object rules, one write per covered pixel) with the constant 1 for the "
      "visibility; the ratio measures what eq. 4-6 add to that pass, as the paper's shader "
      "throughputs do.");
  return r;
}

}  // namespace

std::vector<Check> hegeman_fig2_checks(const Fig2Numbers& n) {
  // The claim is about the paper's model, whose alpha rho the paper tunes by hand: judged at its
  // best scale, the most favourable reading. As derived and tree-volume are reported beside it.
  auto at = [&](const std::string& scene) {
    for (size_t i = 0; i < n.scenes.size(); ++i)
      if (n.scenes[i] == scene && i < n.best.size() && i < n.derived.size() && i < n.volume.size())
        return static_cast<int>(i);
    return -1;
  };
  const int s1 = at("sphere-uniform"), s2 = at("sphere-uniform-dense"), apple = at("tree-apple");
  auto both = [&](const std::vector<TileScore>& v) {
    return fmt(v[static_cast<size_t>(s1)].rmse, 3) + " and " +
           fmt(v[static_cast<size_t>(s2)].rmse, 3);
  };
  std::vector<Check> c;
  if (s1 >= 0 && s2 >= 0) {
    const double worst =
        std::max(n.best[static_cast<size_t>(s1)].rmse, n.best[static_cast<size_t>(s2)].rmse);
    c.push_back(
        {"uniform spheres: eq. 6 at its best alpha rho scale (the paper's model at best) has "
         "tile RMSE <= 0.10 on both (the approximation 'works well')",
         worst <= 0.10,
         "best scale " + both(n.best) + " (as derived " + both(n.derived) + "; tree-volume " +
             both(n.volume) + ")"});
  } else {
    c.push_back({"uniform spheres: eq. 6 at its best scale has tile RMSE <= 0.10 on both", false,
                 "not run"});
  }
  if (apple >= 0) {
    const auto a = static_cast<size_t>(apple);
    c.push_back(
        {"apple tree: eq. 6 at its best scale keeps the 'overall appearance trends': tile "
         "Pearson r with the truth >= 0.5",
         n.best[a].pearson >= 0.5,
         "r = " + fmt(n.best[a].pearson, 3) + " (as derived " + fmt(n.derived[a].pearson, 3) +
             "; tree-volume " + fmt(n.volume[a].pearson, 3) + ")"});
  } else {
    c.push_back(
        {"apple tree: eq. 6 at its best scale has tile Pearson r >= 0.5", false, "not run"});
  }
  return c;
}

std::vector<Check> hegeman_fig8_checks(const Fig8Numbers& n) {
  return {
      {"ellipsoid block RMSE < sphere block RMSE (the ellipsoid approximates the poplar better)",
       n.ellipsoid < n.sphere, fmt(n.ellipsoid, 3) + " vs " + fmt(n.sphere, 3)},
      {"ellipsoid block RMSE < shells block RMSE ('not well approximated by ... multiple "
       "shells')",
       n.ellipsoid < n.shells, fmt(n.ellipsoid, 3) + " vs " + fmt(n.shells, 3)},
      {"mean |ellipsoid - sphere| >= 0.05 over tree pixels (the difference is 'prominent')",
       n.difference >= 0.05, fmt(n.difference, 3)},
  };
}

std::vector<Check> hegeman_fig12_checks(const Fig12Numbers& n) {
  const bool have = n.views.size() == 2 && n.rmse.size() == 2 && n.pearson.size() == 2 &&
                    n.rmse[0].size() == 3 && n.rmse[1].size() == 3 && n.pearson[0].size() == 3 &&
                    n.pearson[1].size() == 3;
  if (!have) return {{"ours, Reeves-Blau and ambient scored in two views", false, "not run"}};
  auto both = [&](auto pred) { return pred(0) && pred(1); };
  auto pair = [&](const std::vector<std::vector<double>>& m, size_t a, size_t b) {
    return n.views[0] + " " + fmt(m[0][a], 3) + " vs " + fmt(m[0][b], 3) + ", " + n.views[1] + " " +
           fmt(m[1][a], 3) + " vs " + fmt(m[1][b], 3);
  };
  return {
      {"tree-pixel RMSE: ours < Reeves-Blau in both views ('much closer to ... an ambient "
       "occlusion solution')",
       both([&](int v) { return n.rmse[v][0] < n.rmse[v][1]; }), pair(n.rmse, 0, 1)},
      {"tree-pixel RMSE: ours < ambient only in both views",
       both([&](int v) { return n.rmse[v][0] < n.rmse[v][2]; }), pair(n.rmse, 0, 2)},
      {"tree-pixel Pearson r with the truth: ours > Reeves-Blau in both views ('richer visual "
       "detail' than R-B's smooth solution)",
       both([&](int v) { return n.pearson[v][0] > n.pearson[v][1]; }), pair(n.pearson, 0, 1)},
  };
}

std::vector<Check> hegeman_throughput_checks(const ThroughputNumbers& n) {
  const std::vector<double>&ours = n.ours, &rb = n.reeves_blau, &amb = n.ambient;
  std::vector<Check> c;
  // Order (paper 2300 > 580 > 460 Mpixel/s): claimed, so each step must be significant.
  const double p1 = p_slower(ours, rb), p2 = p_slower(rb, amb);
  c.push_back(
      {"order: ambient only > Reeves-Blau > ours in Mpixel/s (paper 2300 > 580 > 460): "
       "ours slower than Reeves-Blau and Reeves-Blau slower than ambient, each by the "
       "rank test at p < 0.01",
       p1 < kTimingAlpha && p2 < kTimingAlpha,
       "median ms " + fmt(median(ours), 4) + " / " + fmt(median(rb), 4) + " / " +
           fmt(median(amb), 4) + "; ours > R-B " + p_text(p1) + ", R-B > ambient " + p_text(p2)});
  // Ratios within a factor 2 of the paper's: they fail only where the test puts them outside.
  // Throughput ours/R-B in [0.79 / 2, 0.79 x 2] <=> time ours in [R-B / 1.58, R-B / 0.395].
  auto band = [&](const std::string& rule, const std::vector<double>& other, double paper) {
    const double lo = 1.0 / (2.0 * paper), hi = 2.0 / paper;  // time ratio ours / other
    const double pf = p_faster(ours, other, lo), ps = p_slower(ours, other, hi);
    c.push_back({rule + " (fails only where the rank test puts the time ratio outside [" +
                     fmt(lo, 3) + ", " + fmt(hi, 3) + "] at p < 0.01)",
                 pf >= kTimingAlpha && ps >= kTimingAlpha,
                 "throughput ratio " + fmt(median(other) / median(ours), 3) + "; below band " +
                     p_text(pf) + ", above band " + p_text(ps)});
  };
  band("ours / Reeves-Blau throughput within a factor 2 of the paper's 460/580 = 0.79", rb,
       460.0 / 580.0);
  band("ours / ambient throughput within a factor 2 of the paper's 460/2300 = 0.20", amb,
       460.0 / 2300.0);
  return c;
}

std::vector<Figure> hegeman_figures() {
  return {
      {"hegeman-fig2", "Hegeman et al. 2006, Fig. 2",
       "For two spheres filled with a uniform distribution of small triangles the approximation "
       "V = exp(-alpha rho f V_cap) (eq. 4-6) 'works well'; for an apple tree the error 'is much "
       "larger, but the overall appearance trends are still well preserved'.",
       fig2},
      {"hegeman-fig8", "Hegeman et al. 2006, Fig. 8",
       "An 'ellipsoidal' tree is not well approximated by a single sphere or multiple shells; the "
       "difference between a single spherical shell and a single ellipsoid is prominent.",
       fig8},
      {"hegeman-fig12", "Hegeman et al. 2006, Fig. 12",
       "On an ecosystem, Reeves-Blau gives a pleasing smooth image appropriate as a replacement "
       "for an ambient term, but the approximation of eq. 6 is 'much closer to what one would "
       "expect from an ambient occlusion solution', with a noticeable gain in the trees.",
       fig12},
      {"hegeman-throughput", "Hegeman et al. 2006, §4 (NVShaderPerf)",
       "Fragment throughput on a GeForce 6800 Ultra: 460 Mpixel/s for the approximation, 580 for "
       "Reeves-Blau, 2300 for simple ambient (ratios 0.20 : 0.25 : 1).",
       throughput},
  };
}

}  // namespace aoeval::figures
