#include "sampling/ao_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>

#include "errors.h"

namespace aoeval {

int replicate_count(SamplerKind sampler, int spp) {
  if (sampler == SamplerKind::random) return 1;  // i.i.d. samples: the sample variance is honest
  for (int r : {8, 4, 2})
    if (spp % r == 0 && spp / r >= 1) return r;
  return 1;
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct PixelInput {
  glm::vec3 position, normal, geometric_normal;
  float offset;
};

// Visits every direction of one replicate of one pixel: `visit(direction, above_surface)`.
template <class Visit>
void for_each_direction(const AoTraceSettings& s, uint64_t pixel, uint32_t replicate, uint32_t m,
                        const PixelInput& in, const Frame& frame, std::vector<glm::vec2>& square,
                        Visit&& visit) {
  square.resize(m);
  thread_local std::vector<glm::vec3> local;
  local.resize(m);
  sample_square(s.sampler, s.seed, pixel, replicate, m, square.data());
  if (s.definition.weighting == Weighting::cosine)
    square_to_cosine_hemisphere(square.data(), m, local.data());
  else
    square_to_uniform_hemisphere(square.data(), m, local.data());
  for (uint32_t i = 0; i < m; ++i) {
    const glm::vec3 w = frame.to_world(local[i]);
    visit(w, glm::dot(w, in.geometric_normal) > 0.0f);
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

// Traces one pixel's directions in packets of 16: they share an origin, so a packet traverses the
// top of the BVH together. Directions are written straight into the packet's lanes as they are
// generated; the origin, range and mask are written once per pixel.
class PacketTracer {
 public:
  PacketTracer(RTCScene scene, RTCIntersectContext& context, const AoDefinition& def,
               const PixelInput& in)
      : scene_(scene), context_(context), def_(def), occlusion_only_(def.falloff == Falloff::none) {
    const glm::vec3 o = in.position + in.geometric_normal * in.offset;
    tfar_ = def.bounded() ? static_cast<float>(def.dmax) : kInf;
    RTCRay16& r = occlusion_only_ ? ray_ : hit_.ray;
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

  // Queues direction w, whose value goes to values[index] when the packet is traced.
  void add(const glm::vec3& w, uint32_t index, float* values, uint64_t& traced) {
    RTCRay16& r = occlusion_only_ ? ray_ : hit_.ray;
    r.dir_x[lanes_] = w.x, r.dir_y[lanes_] = w.y, r.dir_z[lanes_] = w.z;
    index_[lanes_++] = index;
    if (lanes_ == 16) flush(values, traced);
  }

  void flush(float* values, uint64_t& traced) {
    if (lanes_ == 0) return;
    alignas(64) int valid[16];
    for (int k = 0; k < 16; ++k) valid[k] = k < lanes_ ? -1 : 0;
    traced += static_cast<uint64_t>(lanes_);
    if (occlusion_only_) {
      for (int k = 0; k < 16; ++k) ray_.tfar[k] = tfar_;
      rtcOccluded16(valid, scene_, &context_, &ray_);
      for (int k = 0; k < lanes_; ++k) values[index_[k]] = ray_.tfar[k] < 0.0f ? 0.0f : 1.0f;
    } else {
      for (int k = 0; k < 16; ++k) {
        hit_.ray.tfar[k] = tfar_;
        hit_.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene_, &context_, &hit_);
      for (int k = 0; k < lanes_; ++k)
        values[index_[k]] =
            hit_.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? 1.0f : def_.ray_value(hit_.ray.tfar[k]);
    }
    lanes_ = 0;
  }

 private:
  RTCScene scene_;
  RTCIntersectContext& context_;
  const AoDefinition& def_;
  bool occlusion_only_;
  float tfar_ = kInf;
  alignas(64) RTCRay16 ray_;
  alignas(64) RTCRayHit16 hit_;
  uint32_t index_[16];
  int lanes_ = 0;
};

// One replicate of one pixel: m directions, traced in packets, values in sample order.
void evaluate_replicate(RTCScene scene, RTCIntersectContext& context, const AoTraceSettings& s,
                        uint64_t pixel, uint32_t replicate, uint32_t m, const PixelInput& in,
                        const Frame& frame, std::vector<glm::vec2>& square,
                        std::vector<glm::vec3>& dirs, std::vector<float>& values,
                        uint64_t& traced) {
  dirs.resize(m);
  values.resize(m);
  PacketTracer tracer(scene, context, s.definition, in);
  for_each_direction(s, pixel, replicate, m, in, frame, square,
                     [&, i = 0u](const glm::vec3& w, bool is_above) mutable {
                       dirs[i] = w;
                       values[i] = 0.0f;  // below the surface: occluded at distance 0
                       if (is_above) tracer.add(w, i, values.data(), traced);
                       ++i;
                     });
  tracer.flush(values.data(), traced);
}

// Running statistics of one pixel: over samples (random) or over replicate means (the others).
struct Accumulator {
  double sum = 0.0, sum_sq = 0.0;
  long count = 0;
  void add(double x) {
    sum += x;
    sum_sq += x * x;
    ++count;
  }
  double mean() const { return count ? sum / static_cast<double>(count) : 0.0; }
  // Standard error of the mean; with no degree of freedom, the bound 0.5 / sqrt(n) of a [0, 1]
  // quantity (the largest possible standard deviation is 0.5).
  double standard_error() const {
    if (count < 2) return 0.5 / std::sqrt(std::max<double>(1.0, static_cast<double>(count)));
    const double n = static_cast<double>(count);
    const double var = std::max(0.0, (sum_sq - sum * sum / n) / (n - 1.0));
    return std::sqrt(var / n);
  }
};

// Running statistics of the bent normal's mean vector m = E[value w] of one pixel, over the same
// units as Accumulator (samples value * w, or replicate means of them): their sum and the sum of
// their outer products, from which the covariance of the mean follows.
struct VectorAccumulator {
  glm::dvec3 sum{0.0};
  // The six distinct sums of the symmetric outer products x x^T (xx, yy, zz, xy, xz, yz): IEEE
  // multiplication commutes, so the mirrored entries are the same bits as a full 3x3 sum's.
  double xx = 0.0, yy = 0.0, zz = 0.0, xy = 0.0, xz = 0.0, yz = 0.0;
  long count = 0;
  void add(const glm::dvec3& x) {
    sum += x;
    xx += x.x * x.x, yy += x.y * x.y, zz += x.z * x.z;
    xy += x.x * x.y, xz += x.x * x.z, yz += x.y * x.z;
    ++count;
  }
  glm::dmat3 outer() const {  // column-major, symmetric
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
    const glm::dvec3 m = n > 0.0 ? sum / n : glm::dvec3(0.0);
    const double len = glm::length(m);
    if (!(len > 0.0)) return 0.0;
    double across = 0.0;
    if (count < 2) {
      across = 1.0 / std::max(1.0, n);
    } else {
      const glm::dmat3 cov = (outer() - glm::outerProduct(sum, sum) / n) / (n - 1.0) / n;
      const glm::dvec3 u = m / len;
      const double trace = cov[0][0] + cov[1][1] + cov[2][2];
      across = std::max(0.0, trace - glm::dot(u, cov * u));
    }
    return std::sqrt(across) / len * (180.0 / std::numbers::pi);
  }
};

}  // namespace

TracedAo trace_ao(const EmbreeScene& es, const GBuffer& g, const AoTraceSettings& s) {
  if (s.spp < 1) throw InputError("--spp: must be at least 1");
  if (s.target_stderr > 0.0 && s.max_spp < s.spp)
    throw InputError("--max-spp: must be at least --spp (" + std::to_string(s.spp) + ")");
  validate_definition(s.definition);
  const auto start = std::chrono::steady_clock::now();
  TracedAo r;
  r.width = g.width;
  r.height = g.height;
  const size_t n = g.pixel_count();
  r.ao.assign(n, 0.0f);
  r.stderr_ao.assign(n, 0.0f);
  r.bent.assign(n, glm::vec3(0.0f));
  r.bent_stderr.assign(n, 0.0f);
  r.coverage = g.coverage;
  r.spp.assign(n, 0.0f);
  const float extent = scene_extent_of(es);
  const int replicates = replicate_count(s.sampler, s.spp);
  const auto m = static_cast<uint32_t>(s.spp / replicates);
  const bool replicated = s.sampler != SamplerKind::random;
  std::atomic<uint64_t> total_traced{0}, total_samples{0};

  parallel_for_embree(
      tbb::blocked_range<int>(0, g.height, 1), [&](const tbb::blocked_range<int>& rows) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        std::vector<glm::vec2> square;
        std::vector<glm::vec3> dirs;
        std::vector<float> values;
        uint64_t traced = 0, samples = 0;
        for (int j = rows.begin(); j < rows.end(); ++j) {
          for (int i = 0; i < g.width; ++i) {
            const size_t k = g.index(i, j);
            if (!g.covered(k)) continue;
            const PixelInput in = pixel_input(g, k, s, extent);
            const Frame frame = make_frame(in.normal);
            Accumulator acc;
            VectorAccumulator bent_acc;
            glm::dvec3 bent(0.0);
            long used = 0;
            for (uint32_t batch = 0;; ++batch) {
              for (int rep = 0; rep < replicates; ++rep) {
                double rep_sum = 0.0;
                glm::dvec3 rep_bent(0.0);
                const auto replicate = static_cast<uint32_t>(batch * replicates + rep);
                evaluate_replicate(es.handle(), context, s, k, replicate, m, in, frame, square,
                                   dirs, values, traced);
                for (uint32_t d = 0; d < m;
                     ++d) {  // in sample order: same bits whatever the packets
                  const float v = values[d];
                  if (v == 0.0f) {
                    // An occluded direction adds zeros (x + 0 = x exactly, and a sum that starts
                    // at +0 stays +0): only the counts move.
                    if (!replicated) ++acc.count, ++bent_acc.count;
                    continue;
                  }
                  const glm::dvec3 weighted = glm::dvec3(dirs[d]) * static_cast<double>(v);
                  if (replicated) {
                    rep_sum += v;
                    rep_bent += weighted;
                    bent += weighted;
                  } else {
                    // bent_acc.sum is the same sum, added in the same order (same bits): the
                    // random sampler's bent normal is read from it below.
                    acc.add(v);
                    bent_acc.add(weighted);
                  }
                }
                if (replicated) {
                  acc.add(rep_sum / m);
                  bent_acc.add(rep_bent / static_cast<double>(m));
                }
                used += m;
              }
              if (s.target_stderr <= 0.0 || acc.standard_error() <= s.target_stderr ||
                  used + s.spp > s.max_spp)
                break;
            }
            samples += static_cast<uint64_t>(used);
            r.ao[k] = static_cast<float>(acc.mean());
            r.stderr_ao[k] = static_cast<float>(acc.standard_error());
            if (!replicated) bent = bent_acc.sum;
            const double len = glm::length(bent);
            r.bent[k] = len > 0.0 ? glm::vec3(bent / len) : glm::vec3(0.0f);
            r.bent_stderr[k] = static_cast<float>(bent_acc.angular_stderr_deg());
            r.spp[k] = static_cast<float>(used);
          }
        }
        total_traced += traced;
        total_samples += samples;
      });
  r.rays_traced = total_traced;
  r.samples = total_samples;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::vector<BareRay> generate_traced_rays(const GBuffer& g, const AoTraceSettings& s,
                                          float scene_extent) {
  std::vector<BareRay> rays;
  std::vector<glm::vec2> square;
  const int replicates = replicate_count(s.sampler, s.spp);
  const auto m = static_cast<uint32_t>(s.spp / replicates);
  const float tfar = s.definition.bounded() ? static_cast<float>(s.definition.dmax) : kInf;
  uint32_t packet = 0;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    if (!g.covered(k)) continue;
    const PixelInput in = pixel_input(g, k, s, scene_extent);
    const Frame frame = make_frame(in.normal);
    for (int rep = 0; rep < replicates; ++rep) {
      int lanes = 0;
      for_each_direction(
          s, k, static_cast<uint32_t>(rep), m, in, frame, square,
          [&](const glm::vec3& w, bool above) {
            if (!above) return;
            if (lanes == 16) ++packet, lanes = 0;
            rays.push_back({in.position + in.geometric_normal * in.offset, w, tfar, packet});
            ++lanes;
          });
      if (lanes > 0) ++packet;
    }
  }
  return rays;
}

}  // namespace aoeval
