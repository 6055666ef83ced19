#include "harness/bench/bench_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "base/resolution.h"
#include "base/summary.h"
#include "references/reference.h"
#include "scenes/corpus.h"

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

// The packet limit: rtcOccluded16 over the reference's own packets (rays of one pixel's replicate,
// 16 lanes, in sample order), pre-built, all cores, nothing else in the loop. The reference
// cannot trace faster than this: the gap to it is ray generation, the sampler, the bookkeeping
// and the accumulation.
struct BarePacket {
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
};

std::vector<BarePacket> packets_of(const std::vector<BareRay>& rays) {
  std::vector<BarePacket> packets;
  for (size_t i = 0; i < rays.size();) {
    BarePacket& p = packets.emplace_back();
    std::memset(&p.ray, 0, sizeof p.ray);
    int lanes = 0;
    const uint32_t id = rays[i].packet;
    for (; i < rays.size() && rays[i].packet == id; ++i, ++lanes) {
      const BareRay& b = rays[i];
      p.ray.org_x[lanes] = b.origin.x, p.ray.org_y[lanes] = b.origin.y,
      p.ray.org_z[lanes] = b.origin.z;
      p.ray.dir_x[lanes] = b.direction.x, p.ray.dir_y[lanes] = b.direction.y,
      p.ray.dir_z[lanes] = b.direction.z;
      p.ray.tfar[lanes] = b.tfar;
      p.ray.mask[lanes] = 0xFFFFFFFFu;
      p.ray.id[lanes] = static_cast<unsigned>(lanes);
    }
    for (int k = 0; k < 16; ++k) p.valid[k] = k < lanes ? -1 : 0;
    for (int k = lanes; k < 16; ++k) p.ray.dir_z[k] = 1.0f;
  }
  return packets;
}

double bare_packet_rays_per_second(RTCScene scene, const std::vector<BarePacket>& packets,
                                   size_t ray_count, uint64_t& occluded_out) {
  std::atomic<uint64_t> occluded{0};
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for_embree(tbb::blocked_range<size_t>(0, packets.size(), 256),
                      [&](const tbb::blocked_range<size_t>& r) {
                        RTCIntersectContext context;
                        rtcInitIntersectContext(&context);
                        uint64_t local = 0;
                        alignas(64) RTCRay16 ray;
                        for (size_t i = r.begin(); i < r.end(); ++i) {
                          ray = packets[i].ray;  // tfar is overwritten by the query
                          rtcOccluded16(packets[i].valid, scene, &context, &ray);
                          for (int k = 0; k < 16; ++k)
                            local += packets[i].valid[k] != 0 && ray.tfar[k] < 0.0f;
                        }
                        occluded += local;
                      });
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  occluded_out = occluded;
  return static_cast<double>(ray_count) / s;
}

double rmse_against(const ReferenceImage& a, const ReferenceImage& truth) {
  double se = 0.0;
  size_t n = 0;
  for (size_t k = 0; k < a.ao.size(); ++k) {
    if (!truth.covered(k)) continue;
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
  const std::vector<BareRay> bare_rays = generate_reference_rays(g, s, extent);
  const std::vector<BarePacket> packets = packets_of(bare_rays);
  for (const BareRay& b : bare_rays) {
    RTCRay r{};
    r.org_x = b.origin.x, r.org_y = b.origin.y, r.org_z = b.origin.z;
    r.dir_x = b.direction.x, r.dir_y = b.direction.y, r.dir_z = b.direction.z;
    r.tnear = 0.0f;
    r.tfar = b.tfar;
    r.mask = 0xFFFFFFFFu;
    rays.push_back(r);
  }
  // Interleave the two measurements, so that drift in the machine's speed hits both alike.
  std::vector<double> reference_rate, bare_rate, packet_rate, ratios, packet_ratios;
  uint64_t traced = 0, occluded = 0, packet_occluded = 0;
  for (int rep = 0; rep < o.repetitions; ++rep) {
    const ReferenceImage r = compute_reference(es, g, s);
    traced = r.rays_traced;
    reference_rate.push_back(static_cast<double>(r.rays_traced) / r.seconds);
    bare_rate.push_back(bare_occlusion_rays_per_second(es.handle(), rays, occluded));
    packet_rate.push_back(
        bare_packet_rays_per_second(es.handle(), packets, rays.size(), packet_occluded));
    ratios.push_back(reference_rate.back() / bare_rate.back());
    packet_ratios.push_back(reference_rate.back() / packet_rate.back());
  }
  if (packet_occluded != occluded)  // the two loops trace the same rays: same answers
    throw std::runtime_error("bench reference: rtcOccluded16 and rtcOccluded1 disagree");
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
  std::printf(
      "  bare rtcOccluded16 loop   %.2f Mrays/s (median of %d; min %.2f, max %.2f; %zu packets)\n",
      median(packet_rate) / 1e6, o.repetitions,
      *std::min_element(packet_rate.begin(), packet_rate.end()) / 1e6,
      *std::max_element(packet_rate.begin(), packet_rate.end()) / 1e6, packets.size());
  std::printf("  ratio reference / bare1   %.3f (median of per-repetition ratios, interleaved)\n",
              median(ratios));
  std::printf("  ratio reference / bare16  %.3f (median of per-repetition ratios, interleaved)\n",
              median(packet_ratios));
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
    if (truth.covered(k)) {
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
