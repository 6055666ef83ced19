// raymarch-ssao: open floor, convergence to the crease's closed form (the same value horizon-split
// AO computes there) as rays grow, determinism and the parameter table.
#include "estimators/raymarch_ssao/raymarch_ssao.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "estimators/registry.h"
#include "estimators/testing/ssao_test_scenes.h"

namespace aoeval {
namespace {

RaymarchSettings crease_settings(int rays, bool attenuation) {
  RaymarchSettings s = raymarch_settings_of(default_params(raymarch_ssao_estimator()));
  s.radius = 0.5;
  s.steps = 64;
  s.rays = rays;
  s.attenuation = attenuation;
  return s;
}

CreaseErrors raymarch_crease_errors(const TestView& view, const RaymarchSettings& s) {
  const std::vector<float> ao = raymarch_ssao(view.gbuffer, s);
  return crease_errors(ao, crease_floor_pixels(view.gbuffer, s.radius + 0.05), s.radius,
                       s.attenuation);
}

TEST(RaymarchSsao, OpenFloorIsUnoccluded) {
  const TestView view = grazing_floor(160, 120);
  RaymarchSettings s = raymarch_settings_of(default_params(raymarch_ssao_estimator()));
  s.rays = 8;
  const std::vector<float> ao = raymarch_ssao(view.gbuffer, s);
  double sum = 0.0;
  size_t n = 0;
  for (int j = 0; j < view.gbuffer.height; ++j) {
    for (int i = 0; i < view.gbuffer.width; ++i) {
      if (!view.gbuffer.covered(view.gbuffer.index(i, j)) ||
          view_angle_deg(view.gbuffer, i, j) > 80)
        continue;
      sum += ao[view.gbuffer.index(i, j)];
      ++n;
    }
  }
  ASSERT_GT(n, 5000u);
  EXPECT_GT(sum / static_cast<double>(n), 0.999);
}

// On the crease the exact bounded AO equals the horizon-split closed form (ssao_test_scenes.h).
// Each ray is a Bernoulli (no attenuation) or bounded value, so the per-pixel error's standard
// deviation is <= 0.5 / sqrt(rays): the RMS error must fall about twofold per fourfold rays (we
// ask 1.6x, leaving room for the fixed discretisation of Ns = 64 steps), and at 64 rays the mean
// over ~1500 pixels within R sits within a few standard errors plus the step bias of the
// closed form.
TEST(RaymarchSsao, ConvergesToTheCreaseClosedFormAsRaysGrow) {
  const TestView view = crease(160, 120);
  for (bool attenuation : {false, true}) {
    const CreaseErrors e4 = raymarch_crease_errors(view, crease_settings(4, attenuation));
    const CreaseErrors e16 = raymarch_crease_errors(view, crease_settings(16, attenuation));
    const CreaseErrors e64 = raymarch_crease_errors(view, crease_settings(64, attenuation));
    std::printf(
        "raymarch crease, attenuation %d: rms %.4f / %.4f / %.4f at 4 / 16 / 64 rays, "
        "bias %.4f at 64\n",
        attenuation, e4.rms, e16.rms, e64.rms, e64.bias);
    EXPECT_LT(e16.rms, e4.rms / 1.6);
    EXPECT_LT(e64.rms, e16.rms / 1.6);
    EXPECT_LT(std::abs(e64.bias), 0.01);
  }
}

TEST(RaymarchSsao, SameSeedSameBits) {
  const TestView view = crease(64, 48);
  RaymarchSettings s = raymarch_settings_of(default_params(raymarch_ssao_estimator()));
  const std::vector<float> a = raymarch_ssao(view.gbuffer, s);
  EXPECT_EQ(a, raymarch_ssao(view.gbuffer, s));
  s.seed = 8;
  EXPECT_NE(a, raymarch_ssao(view.gbuffer, s));
}

TEST(RaymarchSsao, ParametersAndDefinition) {
  const EstimatorInfo& info = find_estimator("raymarch-ssao");
  const ParamSet p = resolve_params(info.name, info.params, {{"R", 0.4}}, "test");
  const AoDefinition d = info.definition(p);
  EXPECT_EQ(d.weighting, Weighting::cosine);
  EXPECT_DOUBLE_EQ(d.dmax, 0.4);
  EXPECT_EQ(d.falloff, Falloff::linear);
  for (const char* bad : {"rays=0", "Ns=0", "R=0", "Nd=4"})
    EXPECT_THROW(resolve_params(info.name, info.params, parse_set_arguments({bad}), "--set"),
                 InputError)
        << bad;
}

}  // namespace
}  // namespace aoeval
