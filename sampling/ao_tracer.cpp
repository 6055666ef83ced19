#include "sampling/ao_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>
#include <span>

#include "base/errors.h"

namespace aoeval {

int replicate_count(SamplerKind sampler, int spp) {
  if (sampler == SamplerKind::random) return 1;  // i.i.d. samples: the sample variance is honest
  for (int r : {8, 4, 2})
    if (spp % r == 0 && spp / r >= 1) return r;
  return 1;
}

int replicates_of(const AoTraceSettings& s) {
  return s.replicates > 0 ? s.replicates : replicate_count(s.sampler, s.spp);
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct PixelInput {
  glm::vec3 position, normal, geometric_normal;
  float offset;
};

// Two doubles added and multiplied lane by lane (GCC/Clang vector extension): the same IEEE
// operations as two scalar ones, so sums kept in lanes are the same bits as sums kept apart.
using Double2 = double __attribute__((vector_size(16)));

// One replicate's directions, as separate coordinate arrays: in the local frame (the hemisphere
// map's output), in world space, and whether each lies above the geometric surface.
struct ReplicateDirections {
  std::vector<glm::vec2> square;
  std::vector<float> local_x, local_y, local_z, x, y, z;
  std::vector<uint8_t> above;
};

// Draws replicate `replicate` of pixel `pixel`: m directions in sample order. The world-space loop
// does Frame::to_world's and glm::dot's operations in their order, lane by lane, so it vectorises
// and gives the same bits as the per-direction calls.
void make_directions(const AoTraceSettings& s, uint64_t pixel, uint32_t replicate, uint32_t m,
                     const PixelInput& in, const Frame& frame, ReplicateDirections& d) {
  for (auto* v : {&d.local_x, &d.local_y, &d.local_z, &d.x, &d.y, &d.z}) v->resize(m);
  d.square.resize(m);
  d.above.resize(m);
  sample_square(s.sampler, s.seed, pixel, replicate, m, d.square.data(), s.first_sample);
  if (s.definition.weighting == Weighting::cosine)
    square_to_cosine_hemisphere(d.square.data(), m, d.local_x.data(), d.local_y.data(),
                                d.local_z.data());
  else
    square_to_uniform_hemisphere(d.square.data(), m, d.local_x.data(), d.local_y.data(),
                                 d.local_z.data());
  const glm::vec3 t = frame.t, b = frame.b, n = frame.n, ng = in.geometric_normal;
  const float *lx = d.local_x.data(), *ly = d.local_y.data(), *lz = d.local_z.data();
  float *x = d.x.data(), *y = d.y.data(), *z = d.z.data();
  uint8_t* above = d.above.data();
  for (uint32_t i = 0; i < m; ++i) {
    const float wx = t.x * lx[i] + b.x * ly[i] + n.x * lz[i];
    const float wy = t.y * lx[i] + b.y * ly[i] + n.y * lz[i];
    const float wz = t.z * lx[i] + b.z * ly[i] + n.z * lz[i];
    x[i] = wx, y[i] = wy, z[i] = wz;
    above[i] = wx * ng.x + wy * ng.y + wz * ng.z > 0.0f;
  }
}

PixelInput pixel_input(const GBuffer& g, size_t k, const AoTraceSettings& s, float extent) {
  PixelInput in;
  in.position = g.position[k];
  in.geometric_normal = g.geometric_normal[k];
  in.normal = s.normal == NormalMode::shading ? g.normal[k] : g.geometric_normal[k];
  in.offset = origin_offset(in.position, extent);
  return in;
}

float scene_extent_of(const EmbreeScene& es) {
  const glm::vec3 e = es.scene().bounds().extent();
  return std::max({e.x, e.y, e.z});
}

// Running statistics of one pixel: over samples (random) or over replicate means (the others).
struct Accumulator {
  Double2 sums = {0.0, 0.0};  // the sum and the sum of squares
  long count = 0;
  void add(double x) {
    sums += Double2{x, x * x};
    ++count;
  }
  double mean() const { return count ? sums[0] / static_cast<double>(count) : 0.0; }
  // Standard error of the mean; with no degree of freedom, the bound 0.5 / sqrt(n) of a [0, 1]
  // quantity (the largest possible standard deviation is 0.5).
  double standard_error() const {
    if (count < 2) return 0.5 / std::sqrt(std::max<double>(1.0, static_cast<double>(count)));
    const double n = static_cast<double>(count), sum = sums[0];
    const double var = std::max(0.0, (sums[1] - sum * sum / n) / (n - 1.0));
    return std::sqrt(var / n);
  }
};

// Running statistics of the bent normal's mean vector m = E[value w] of one pixel, over the same
// units as Accumulator (samples value * w, or replicate means of them): their sum and the sum of
// their outer products, from which the covariance of the mean follows.
struct VectorAccumulator {
  Double2 sum_xy = {0.0, 0.0};
  double sum_z = 0.0;
  // The six distinct sums of the symmetric outer products x x^T, two per lane pair: IEEE
  // multiplication commutes, so the mirrored entries are the same bits as a full 3x3 sum's.
  Double2 xx_yy = {0.0, 0.0}, zz_xy = {0.0, 0.0}, xz_yz = {0.0, 0.0};
  long count = 0;
  void add(const glm::dvec3& x) {
    const Double2 xy = {x.x, x.y};
    sum_xy += xy;
    sum_z += x.z;
    xx_yy += xy * xy;
    zz_xy += Double2{x.z, x.x} * Double2{x.z, x.y};
    xz_yz += xy * Double2{x.z, x.z};
    ++count;
  }
  glm::dvec3 sum() const { return glm::dvec3(sum_xy[0], sum_xy[1], sum_z); }
  glm::dmat3 outer() const {  // column-major, symmetric
    const double xx = xx_yy[0], yy = xx_yy[1], zz = zz_xy[0], xy = zz_xy[1], xz = xz_yz[0],
                 yz = xz_yz[1];
    return glm::dmat3(xx, xy, xz, xy, yy, yz, xz, yz, zz);
  }
  // The angular standard error of the unit mean direction, degrees: with C the covariance of the
  // mean vector (sample covariance / n) and u = m / |m|, the error of m across u has variance
  // tr(C) - u^T C u (both axes), and a small error e across u turns the direction by |e| / |m|
  // radians, so E[angle^2] = (tr(C) - u^T C u) / |m|^2: the value is its square root, the rms
  // angle between the reference's bent normal and its expectation. With fewer than two units,
  // the bound of a unit vector weighted by a value in [0, 1] (second moment <= 1): 1 / sqrt(n).
  // 0 where m = 0 (no bent normal).
  double angular_stderr_deg() const {
    const double n = static_cast<double>(count);
    const glm::dvec3 total = sum();
    const glm::dvec3 m = n > 0.0 ? total / n : glm::dvec3(0.0);
    const double len = glm::length(m);
    if (!(len > 0.0)) return 0.0;
    double across = 0.0;
    if (count < 2) {
      across = 1.0 / std::max(1.0, n);
    } else {
      const glm::dmat3 cov = (outer() - glm::outerProduct(total, total) / n) / (n - 1.0) / n;
      const glm::dvec3 u = m / len;
      const double trace = cov[0][0] + cov[1][1] + cov[2][2];
      across = std::max(0.0, trace - glm::dot(u, cov * u));
    }
    return std::sqrt(across) / len * (180.0 / std::numbers::pi);
  }
};

// The sums of one pixel, fed each direction's value in sample order (the same bits whatever the
// packets). Occluded directions add zeros (x + 0 = x exactly, and a sum that starts at +0 stays
// +0), so for them only the counts move.
struct PixelSums {
  explicit PixelSums(bool replicated_samples) : replicated(replicated_samples) {}
  bool replicated;  // stratified and sobol: statistics over replicate means, not samples
  Accumulator acc;
  VectorAccumulator bent_acc;
  double replicate_sum = 0.0;
  glm::dvec3 replicate_bent{0.0};
  glm::dvec3 bent{0.0};  // replicated: the sum of value * w (random reads bent_acc's sum)

  void occluded() {
    if (!replicated) ++acc.count, ++bent_acc.count;
  }
  // value 1: w itself (w * 1.0 would be the same bits).
  void unoccluded(const glm::vec3& w) { add(1.0, glm::dvec3(w)); }
  // value 1 if `open`, else 0, without a branch (occlusion is unpredictable from ray to ray): an
  // occluded direction adds 0 and w * 0 = +-0, which leave every sum's bits as they are (no sum is
  // ever -0: each starts at +0, and x + (-x) = +0), and moves the counts as occluded() does.
  void occlusion(const glm::vec3& w, bool open) {
    const auto value = static_cast<double>(open);  // a conversion, which compiles without a jump
    add(value, glm::dvec3(w) * value);
  }
  void partly_occluded(const glm::vec3& w, float value) {
    if (value == 0.0f) return occluded();
    add(value, glm::dvec3(w) * static_cast<double>(value));
  }
  void end_replicate(uint32_t m) {
    if (!replicated) return;
    acc.add(replicate_sum / m);
    bent_acc.add(replicate_bent / static_cast<double>(m));
    replicate_sum = 0.0;
    replicate_bent = glm::dvec3(0.0);
  }
  glm::dvec3 bent_sum() const { return replicated ? bent : bent_acc.sum(); }

 private:
  void add(double value, const glm::dvec3& weighted) {
    if (replicated) {
      replicate_sum += value;
      replicate_bent += weighted;
      bent += weighted;
    } else {
      acc.add(value);
      bent_acc.add(weighted);
    }
  }
};

// How a trace's rays end. `bounded`: each ray stops at the one definition's dmax, any hit for
// falloff none (rtcOccluded), the closest for the others: the least work for one definition (the
// raytraced and rtao estimators, whose cost is timed). `shared`: the closest hit with no bound
// (rtcIntersect, tfar = infinity), from which every definition's value follows (ray_value(t): a hit
// at t >= dmax is a miss for it); a lone unbounded definition with falloff none only asks whether
// anything is hit, which rtcOccluded answers with the same bits (both accept exactly the hits the
// same triangle tests accept). The references trace `shared`, alone or several definitions at once
// (trace_ao_definitions), so one definition's bits are the same whichever others share its rays:
// the Embree calls are the same calls.
enum class RayRange { bounded, shared };

// Traces one pixel's directions in packets of 16: they share an origin, so a packet traverses the
// top of the BVH together. Directions are written straight into the packet's lanes as they are
// generated; the origin, range and mask are written once per pixel. Each traced packet's values go
// to every definition's sums at once, in lane (= sample) order.
class PacketTracer {
 public:
  PacketTracer(RTCScene scene, RTCIntersectContext& context, std::span<const AoDefinition> defs,
               RayRange range, const PixelInput& in, std::span<PixelSums> sums)
      : scene_(scene),
        context_(context),
        defs_(defs),
        sums_(sums),
        occlusion_only_(defs.size() == 1 && defs[0].falloff == Falloff::none &&
                        (range == RayRange::bounded || !defs[0].bounded())),
        rays_(occlusion_only_ ? &ray_ : &hit_.ray) {
    const glm::vec3 o = in.position + in.geometric_normal * in.offset;
    tfar_ =
        range == RayRange::bounded && defs[0].bounded() ? static_cast<float>(defs[0].dmax) : kInf;
    RTCRay16& r = *rays_;
    for (int k = 0; k < 16; ++k) {
      r.org_x[k] = o.x, r.org_y[k] = o.y, r.org_z[k] = o.z;
      r.dir_x[k] = 0.0f, r.dir_y[k] = 0.0f, r.dir_z[k] = 1.0f;
      r.tnear[k] = 0.0f;
      r.time[k] = 0.0f;
      r.mask[k] = 0xFFFFFFFFu;
      r.id[k] = static_cast<unsigned>(k);
      r.flags[k] = 0;
    }
  }

  // Queues direction w; its value goes to the sums when its packet is traced.
  void add(float x, float y, float z, uint64_t& traced) {
    RTCRay16& r = *rays_;
    r.dir_x[lanes_] = x, r.dir_y[lanes_] = y, r.dir_z[lanes_] = z;
    if (++lanes_ == 16) flush(traced);
  }

  // Traces 16 directions at once as a full packet; only when no direction is queued.
  void add_packet(const float* x, const float* y, const float* z, uint64_t& traced) {
    RTCRay16& r = *rays_;
    std::copy_n(x, 16, r.dir_x);
    std::copy_n(y, 16, r.dir_y);
    std::copy_n(z, 16, r.dir_z);
    lanes_ = 16;
    flush(traced);
  }
  bool empty() const { return lanes_ == 0; }

  void flush(uint64_t& traced) {
    if (lanes_ == 0) return;
    alignas(64) int valid[16];
    for (int k = 0; k < 16; ++k) valid[k] = k < lanes_ ? -1 : 0;
    traced += static_cast<uint64_t>(lanes_);
    const RTCRay16& r = *rays_;
    if (occlusion_only_) {
      for (int k = 0; k < 16; ++k) ray_.tfar[k] = tfar_;
      rtcOccluded16(valid, scene_, &context_, &ray_);
      // Summed in a local copy, which the compiler keeps in registers (the pixel's sums behind a
      // reference stay in memory, a store and a load per addition).
      PixelSums local = sums_[0];
      for (int k = 0; k < lanes_; ++k)
        local.occlusion(glm::vec3(r.dir_x[k], r.dir_y[k], r.dir_z[k]), ray_.tfar[k] >= 0.0f);
      sums_[0] = local;
    } else {
      for (int k = 0; k < 16; ++k) {
        hit_.ray.tfar[k] = tfar_;
        hit_.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene_, &context_, &hit_);
      // Each definition's values from the same hit distances, in sample order per definition.
      for (size_t d = 0; d < defs_.size(); ++d) {
        const AoDefinition& def = defs_[d];
        PixelSums local = sums_[d];
        for (int k = 0; k < lanes_; ++k) {
          const glm::vec3 w(r.dir_x[k], r.dir_y[k], r.dir_z[k]);
          if (hit_.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID)
            local.unoccluded(w);
          else
            local.partly_occluded(w, def.ray_value(hit_.ray.tfar[k]));
        }
        sums_[d] = local;
      }
    }
    lanes_ = 0;
  }

 private:
  RTCScene scene_;
  RTCIntersectContext& context_;
  std::span<const AoDefinition> defs_;
  std::span<PixelSums> sums_;
  bool occlusion_only_;
  RTCRay16* rays_;  // the packet's rays: ray_, or hit_'s rays when distances are needed
  float tfar_ = kInf;
  alignas(64) RTCRay16 ray_;
  alignas(64) RTCRayHit16 hit_;
  int lanes_ = 0;
};

// Whether the 16 flags from `above` on are all set (each flag is 0 or 1).
bool all_above(const uint8_t* above) {
  uint64_t low, high;
  std::memcpy(&low, above, 8);
  std::memcpy(&high, above + 8, 8);
  constexpr uint64_t kAllOnes = 0x0101010101010101u;
  return low == kAllOnes && high == kAllOnes;
}

// One replicate of one pixel: m directions, traced in packets, their values summed in sample
// order into every definition's sums. Directions below the geometric surface are occluded at
// distance 0 and not traced.
void evaluate_replicate(RTCScene scene, RTCIntersectContext& context, const AoTraceSettings& s,
                        std::span<const AoDefinition> defs, RayRange range, uint64_t pixel,
                        uint32_t replicate, uint32_t m, const PixelInput& in, const Frame& frame,
                        ReplicateDirections& d, std::span<PixelSums> sums, uint64_t& traced) {
  make_directions(s, pixel, replicate, m, in, frame, d);
  PacketTracer tracer(scene, context, defs, range, in, sums);
  for (uint32_t i = 0; i < m;) {
    // Sixteen directions above the surface in a row (nearly always): one copy into the packet.
    if (tracer.empty() && m - i >= 16 && all_above(d.above.data() + i)) {
      tracer.add_packet(d.x.data() + i, d.y.data() + i, d.z.data() + i, traced);
      i += 16;
      continue;
    }
    if (d.above[i])
      tracer.add(d.x[i], d.y[i], d.z[i], traced);
    else
      for (PixelSums& one : sums) one.occluded();
    ++i;
  }
  tracer.flush(traced);
  for (PixelSums& one : sums) one.end_replicate(m);
}

void check_settings(const AoTraceSettings& s) {
  if (s.spp < 1) throw InputError("--spp: must be at least 1");
  if (s.target_stderr > 0.0 && s.max_spp < s.spp)
    throw InputError("--max-spp: must be at least --spp (" + std::to_string(s.spp) + ")");
  if (s.spp % replicates_of(s) != 0)
    throw InputError("replicates: " + std::to_string(replicates_of(s)) + " does not divide " +
                     std::to_string(s.spp) + " rays per pixel");
}

// The trace of `defs` (one weighting; s.definition is defs[0]) from one set of rays: one image per
// definition, each with its own mean, standard error and bent normal. Adaptive sampling
// (target_stderr) stops on the first definition's standard error.
std::vector<TracedAo> trace(const EmbreeScene& es, const GBuffer& g, const AoTraceSettings& s,
                            std::span<const AoDefinition> defs, RayRange range) {
  const auto start = std::chrono::steady_clock::now();
  const size_t n = g.pixel_count();
  std::vector<TracedAo> out(defs.size());
  for (TracedAo& r : out) {
    r.width = g.width;
    r.height = g.height;
    r.ao.assign(n, 0.0f);
    r.stderr_ao.assign(n, 0.0f);
    r.bent.assign(n, glm::vec3(0.0f));
    r.bent_stderr.assign(n, 0.0f);
    r.coverage = g.coverage;
    r.spp.assign(n, 0.0f);
  }
  const float extent = scene_extent_of(es);
  const int replicates = replicates_of(s);
  const auto m = static_cast<uint32_t>(s.spp / replicates);
  const bool replicated = s.sampler != SamplerKind::random;
  std::atomic<uint64_t> total_traced{0}, total_samples{0};

  parallel_for_embree(
      tbb::blocked_range<int>(0, g.height, 1), [&](const tbb::blocked_range<int>& rows) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        ReplicateDirections directions;
        std::vector<PixelSums> sums;
        uint64_t traced = 0, samples = 0;
        for (int j = rows.begin(); j < rows.end(); ++j) {
          for (int i = 0; i < g.width; ++i) {
            const size_t k = g.index(i, j);
            if (!g.covered(k)) continue;
            const PixelInput in = pixel_input(g, k, s, extent);
            const Frame frame = make_frame(in.normal);
            sums.assign(defs.size(), PixelSums(replicated));
            long used = 0;
            for (uint32_t batch = 0;; ++batch) {
              for (int rep = 0; rep < replicates; ++rep) {
                const auto replicate = static_cast<uint32_t>(batch * replicates + rep);
                evaluate_replicate(es.handle(), context, s, defs, range, k, replicate, m, in, frame,
                                   directions, sums, traced);
                used += m;
              }
              if (s.target_stderr <= 0.0 || sums[0].acc.standard_error() <= s.target_stderr ||
                  used + s.spp > s.max_spp)
                break;
            }
            samples += static_cast<uint64_t>(used);
            for (size_t d = 0; d < defs.size(); ++d) {
              TracedAo& r = out[d];
              r.ao[k] = static_cast<float>(sums[d].acc.mean());
              r.stderr_ao[k] = static_cast<float>(sums[d].acc.standard_error());
              const glm::dvec3 bent = sums[d].bent_sum();
              const double len = glm::length(bent);
              r.bent[k] = len > 0.0 ? glm::vec3(bent / len) : glm::vec3(0.0f);
              r.bent_stderr[k] = static_cast<float>(sums[d].bent_acc.angular_stderr_deg());
              r.spp[k] = static_cast<float>(used);
            }
          }
        }
        total_traced += traced;
        total_samples += samples;
      });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (TracedAo& r : out) {
    r.rays_traced = total_traced;
    r.samples = total_samples;
    r.seconds = seconds;
  }
  return out;
}

}  // namespace

TracedAo trace_ao(const EmbreeScene& es, const GBuffer& g, const AoTraceSettings& s) {
  check_settings(s);
  validate_definition(s.definition);
  return std::move(trace(es, g, s, std::span(&s.definition, 1), RayRange::bounded)[0]);
}

std::vector<TracedAo> trace_ao_definitions(const EmbreeScene& es, const GBuffer& g,
                                           const AoTraceSettings& settings,
                                           const std::vector<AoDefinition>& definitions) {
  if (definitions.empty()) return {};
  check_settings(settings);
  for (const AoDefinition& d : definitions) {
    validate_definition(d);
    if (d.weighting != definitions[0].weighting)
      throw InputError("reference definitions: " + d.label() + " and " + definitions[0].label() +
                       " draw different directions (one trace per weighting)");
  }
  if (definitions.size() > 1 && settings.target_stderr > 0.0)
    throw InputError("--target-stderr: adaptive sampling traces one definition at a time");
  AoTraceSettings s = settings;
  s.definition = definitions[0];
  return trace(es, g, s, definitions, RayRange::shared);
}

std::vector<BareRay> generate_traced_rays(const GBuffer& g, const AoTraceSettings& s,
                                          float scene_extent) {
  std::vector<BareRay> rays;
  ReplicateDirections d;
  const int replicates = replicates_of(s);
  const auto m = static_cast<uint32_t>(s.spp / replicates);
  const float tfar = s.definition.bounded() ? static_cast<float>(s.definition.dmax) : kInf;
  uint32_t packet = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    if (!g.covered(k)) continue;
    const PixelInput in = pixel_input(g, k, s, scene_extent);
    const Frame frame = make_frame(in.normal);
    const glm::vec3 origin = in.position + in.geometric_normal * in.offset;
    for (int rep = 0; rep < replicates; ++rep) {
      make_directions(s, k, static_cast<uint32_t>(rep), m, in, frame, d);
      int lanes = 0;
      for (uint32_t i = 0; i < m; ++i) {
        if (!d.above[i]) continue;
        if (lanes == 16) ++packet, lanes = 0;
        rays.push_back({origin, glm::vec3(d.x[i], d.y[i], d.z[i]), tfar, packet});
        ++lanes;
      }
      if (lanes > 0) ++packet;
    }
  }
  return rays;
}

}  // namespace aoeval
