#include "harness/bench/bench_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "corpus.h"
#include "harness/cli/commands.h"
#include "harness/results/summary.h"
#include "references/reference.h"

namespace aoeval {

namespace {

// The practical limit: rtcOccluded1 over pre-generated rays, all cores, nothing else in the loop.
double bare_occlusion_rays_per_second(RTCScene scene, const std::vector<RTCRay>& rays,
                                      uint64_t& occluded_out) {
  std::atomic<uint64_t> occluded{0};
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for_embree(tbb::blocked_range<size_t>(0, rays.size(), 4096),
                      [&](const tbb::blocked_range<size_t>& r) {
                        RTCIntersectContext context;
                        rtcInitIntersectContext(&context);
                        uint64_t local = 0;
                        for (size_t i = r.begin(); i < r.end(); ++i) {
                          RTCRay ray = rays[i];
                          rtcOccluded1(scene, &context, &ray);
                          local += ray.tfar < 0.0f;
                        }
                        occluded += local;
                      });
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  occluded_out = occluded;
  return static_cast<double>(rays.size()) / s;
}

double rmse_against(const ReferenceImage& a, const ReferenceImage& truth) {
  double se = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < a.ao.size(); ++k) {
    if (truth.coverage[k] < 0.5f) continue;
    const double d = static_cast<double>(a.ao[k]) - truth.ao[k];
    se += d * d;
    ++n;
  }
  return n ? std::sqrt(se / static_cast<double>(n)) : 0.0;
}

}  // namespace

void bench_reference(const ReferenceBenchOptions& o) {
  const auto [w, h] = parse_resolution(o.res);
  Scene scene = load_scene(o.scene);
  const View& view = scene.view(o.view);
  EmbreeScene es(scene);
  const Camera camera = make_camera(view, w, h);
  const GBuffer g = render_gbuffer(es, camera);
  ReferenceSettings s;
  s.spp = o.spp;
  s.sampler = SamplerKind::random;  // the bare loop replays the random sampler's rays
  const glm::vec3 e = scene.bounds().extent();
  const float extent = std::max({e.x, e.y, e.z});

  std::printf("bench reference: scene %s, view %s, %dx%d, %d spp, cosine, unbounded, random\n",
              scene.name.c_str(), view.name.c_str(), camera.width, camera.height, s.spp);
  // Pre-generate the very rays the reference traces, as Embree ray structures.
  std::vector<RTCRay> rays;
  for (const BareRay& b : generate_reference_rays(g, s, extent)) {
    RTCRay r{};
    r.org_x = b.origin.x, r.org_y = b.origin.y, r.org_z = b.origin.z;
    r.dir_x = b.direction.x, r.dir_y = b.direction.y, r.dir_z = b.direction.z;
    r.tnear = 0.0f;
    r.tfar = b.tfar;
    r.mask = 0xFFFFFFFFu;
    rays.push_back(r);
  }
  // Interleave the two measurements, so that drift in the machine's speed hits both alike.
  std::vector<double> reference_rate, bare_rate, ratios;
  uint64_t traced = 0, occluded = 0;
  for (int rep = 0; rep < o.repetitions; ++rep) {
    const ReferenceImage r = compute_reference(es, g, s);
    traced = r.rays_traced;
    reference_rate.push_back(static_cast<double>(r.rays_traced) / r.seconds);
    bare_rate.push_back(bare_occlusion_rays_per_second(es.handle(), rays, occluded));
    ratios.push_back(reference_rate.back() / bare_rate.back());
  }
  std::printf("  rays per frame            %llu traced (%zu pre-generated), %.1f%% occluded\n",
              static_cast<unsigned long long>(traced), rays.size(),
              100.0 * static_cast<double>(occluded) /
                  static_cast<double>(std::max<size_t>(1, rays.size())));
  std::printf("  reference                 %.2f Mrays/s (median of %d; min %.2f, max %.2f)\n",
              median(reference_rate) / 1e6, o.repetitions,
              *std::min_element(reference_rate.begin(), reference_rate.end()) / 1e6,
              *std::max_element(reference_rate.begin(), reference_rate.end()) / 1e6);
  std::printf("  bare rtcOccluded1 loop    %.2f Mrays/s (median of %d; min %.2f, max %.2f)\n",
              median(bare_rate) / 1e6, o.repetitions,
              *std::min_element(bare_rate.begin(), bare_rate.end()) / 1e6,
              *std::max_element(bare_rate.begin(), bare_rate.end()) / 1e6);
  std::printf("  ratio reference / bare    %.3f (median of per-pair ratios)\n", median(ratios));
  std::fflush(stdout);
  if (o.skip_accuracy) return;

  // Sampler accuracy at equal rays against a high-spp truth of the same view.
  const auto [aw, ah] = parse_resolution(o.accuracy_res, "--accuracy-res");
  const Camera small = make_camera(view, aw, ah);
  const GBuffer gs = render_gbuffer(es, small);
  ReferenceSettings truth_settings;
  truth_settings.spp = o.truth_spp;
  truth_settings.sampler = SamplerKind::sobol;
  truth_settings.seed = 987654321;
  const ReferenceImage truth = compute_reference(es, gs, truth_settings);
  double truth_se2 = 0.0;
  size_t covered = 0;
  for (size_t k = 0; k < truth.ao.size(); ++k)
    if (truth.coverage[k] > 0.5f) {
      truth_se2 += static_cast<double>(truth.stderr_ao[k]) * truth.stderr_ao[k];
      ++covered;
    }
  std::printf(
      "sampler accuracy: %dx%d, %d spp against a %d-spp sobol truth (its rms stderr %.5f)\n", aw,
      ah, s.spp, o.truth_spp, covered ? std::sqrt(truth_se2 / covered) : 0.0);
  double random_rmse = 0.0;
  for (SamplerKind kind : {SamplerKind::random, SamplerKind::stratified, SamplerKind::sobol}) {
    ReferenceSettings ks;
    ks.spp = s.spp;
    ks.sampler = kind;
    const ReferenceImage r = compute_reference(es, gs, ks);
    const double rmse = rmse_against(r, truth);
    if (kind == SamplerKind::random) random_rmse = rmse;
    std::printf("  %-10s rmse %.5f  (x%.3f of random)  %.2f Mrays/s\n", sampler_name(kind), rmse,
                random_rmse > 0 ? rmse / random_rmse : 1.0, r.rays_traced / 1e6 / r.seconds);
  }
}

}  // namespace aoeval
