// raymarch-ssao: Monte-Carlo ray marching in the depth buffer with hbao-split's march (see
// raymarch_ssao.h).
#include "estimators/raymarch_ssao/raymarch_ssao.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.h"
#include "estimators/hbao_split/hbao_split.h"
#include "sampling/samplers.h"
#include "scenes/random.h"

// hbao-split's kernel: this file uses its pixel set-up (P' of eq. 13, the normal, a tangent frame)
// and its linear search along a ray (hbao_march).
#include "estimators/hbao_split/hbao_cpu_kernel.h"

namespace aoeval::hbao_glsl {
namespace raymarch {
inline float hbao_depth(const HbaoImages& img, int i, int j) {
  return img.depth[pixel_of(img, i, j)];
}
#include "estimators/hbao_split/hbao_kernel.glsl"
}  // namespace raymarch
}  // namespace aoeval::hbao_glsl

#include "estimators/hbao_split/hbao_cpu_kernel_end.h"
#include "estimators/seed_param.h"

namespace aoeval {

namespace {

HbaoSettings march_settings(const RaymarchSettings& s) {
  HbaoSettings h{};  // blur and seed stay 0: the march reads neither
  h.radius = s.radius;
  h.steps = s.steps;
  h.attenuation = s.attenuation;
  h.offset = s.offset;
  h.jitter = false;  // hbao's texture is unused here: the pixel set-up reads (1, 0, 0)
  h.tile = 1;
  h.directions = 1;
  h.normal_rays = 0;
  return h;
}

}  // namespace

RaymarchSettings raymarch_settings_of(const ParamSet& p) {
  RaymarchSettings s{};
  s.radius = p.real("R");
  s.steps = static_cast<int>(p.integer("Ns"));
  s.rays = static_cast<int>(p.integer("rays"));
  s.attenuation = p.boolean("attenuation");
  s.offset = p.boolean("offset");
  s.seed = static_cast<uint64_t>(p.integer("seed"));
  return s;
}

namespace {

AoDefinition definition_of(const RaymarchSettings& s) {
  AoDefinition d;
  d.dmax = s.radius;
  d.falloff = s.attenuation ? Falloff::linear : Falloff::none;
  return d;
}

class RaymarchEstimator : public Estimator {
 public:
  explicit RaymarchEstimator(const ParamSet& p) : settings_(raymarch_settings_of(p)) {}
  EstimateResult run(const EstimateContext& context) override {
    EstimateResult r;
    r.ao = raymarch_ssao(context.gbuffer, settings_);
    return r;
  }

 private:
  RaymarchSettings settings_;
};

}  // namespace

std::vector<float> raymarch_ssao(const GBuffer& gbuffer, const RaymarchSettings& s) {
  const ScreenSpaceFrame frame = screen_space_frame_from_gbuffer(gbuffer);
  validate_hbao_frame(frame);
  const HbaoSettings hs = march_settings(s);
  const HbaoConstants c = hbao_constants(hs, frame);
  const std::vector<glm::vec3> random = hbao_random_texture(hs);
  hbao_glsl::HbaoImages images;
  images.width = frame.width;
  images.pixels = frame.depth.size();
  images.depth = frame.depth.data();
  images.normal = frame.normal.data();
  images.random = random.data();
  images.tile = 1;

  const auto m = static_cast<uint32_t>(s.rays);
  std::vector<float> ao(frame.depth.size(), 0.0f);
  tbb::parallel_for(tbb::blocked_range<int>(0, frame.height, 1),
                    [&](const tbb::blocked_range<int>& rows) {
                      std::vector<glm::vec2> square(m);
                      for (int j = rows.begin(); j < rows.end(); ++j) {
                        for (int i = 0; i < frame.width; ++i) {
                          hbao_glsl::raymarch::HbaoPixel px;
                          if (!hbao_glsl::raymarch::hbao_setup_pixel(images, i, j, c, px)) continue;
                          const size_t k = hbao_glsl::pixel_of(images, i, j);
                          // i.i.d. cosine-distributed directions (pdf cos/pi: eq. 1 is their mean
                          // value) and one step jitter per ray, all from (seed, pixel).
                          sample_square(SamplerKind::random, s.seed, k, 0, m, square.data());
                          SplitMix64 jitter(mix_seed(s.seed, k, 0x524D5353));  // "RMSS"
                          double sum = 0.0;
                          for (uint32_t n = 0; n < m; ++n) {
                            const glm::vec3 local = square_to_cosine_hemisphere(square[n]);
                            const glm::vec3 r = px.b1 * local.x + px.b2 * local.y + px.n * local.z;
                            const float beta = 2.0f * jitter.uniform_float() - 1.0f;
                            sum += 1.0f - hbao_glsl::raymarch::hbao_march(images, px.p, r, beta, c);
                          }
                          ao[k] = static_cast<float>(sum / m);
                        }
                      }
                    });
  return ao;
}

EstimatorInfo raymarch_ssao_estimator() {
  EstimatorInfo info;
  info.name = "raymarch-ssao";
  info.summary =
      "Monte-Carlo ray marching in the depth buffer: the baseline of Dimitrov et al. 2008 Fig. 12";
  info.paper =
      "Dimitrov, Bavoil, Sainz 2008, Horizon-Split Ambient Occlusion: the ray-marching baseline "
      "(§5, Fig. 12) of eq. 1 with cosine-distributed rays, marched like the normal rays of §3.3 "
      "(Fig. 4's ISBELOW/INTERSECT on nearest texels, §4.1.1), eq. 13 offset, §3.5 attenuation";
  info.backend = Backend::cpu;
  info.inputs = {EstimatorInput::gbuffer};
  info.params = {
      real_param(
          {.name = "R",
           .def = 0.3,
           .min = 1e-4,
           .max = 1e4,
           .spacing = Spacing::log,
           .unit = "scene units",
           .meaning = "radius of influence: rays stop at distance R (hbao-split's R, §3.6)"}),
      int_param({.name = "Ns",
                 .def = 18,
                 .min = 1,
                 .max = 256,
                 .spacing = Spacing::linear,
                 .unit = "steps",
                 .meaning = "steps of R / Ns per ray, jittered by beta in (-1, 1) (§3.6, §4.1.2)"}),
      int_param(
          {.name = "rays",
           .def = 16,
           .min = 1,
           .max = 4096,
           .spacing = Spacing::log,
           .unit = "rays",
           .meaning =
               "cosine-distributed rays per pixel (eq. 1 by Monte Carlo; Fig. 12's ray count)"}),
      bool_param({.name = "attenuation",
                  .def = true,
                  .meaning = "weight an occluder at distance r by 1 - r/R (§3.5); the definition's "
                             "linear falloff"}),
      bool_param(
          {.name = "offset",
           .def = true,
           .meaning =
               "start rays at P' = P + z/(f res) n against banding at grazing angles (eq. 13)"}),
      seed_param("seed of the ray directions and step jitters"),
  };
  info.definition_doc =
      "cosine weighting (eq. 1), dmax = R, falloff linear when attenuation is on (an occluder at "
      "distance r < R counts 1 - r/R, §3.5), none when off; only what the depth buffer shows "
      "within R of P' can occlude";
  info.definition = [](const ParamSet& p) { return definition_of(raymarch_settings_of(p)); };
  info.create = [](const ParamSet& p) { return std::make_unique<RaymarchEstimator>(p); };
  return info;
}

}  // namespace aoeval
