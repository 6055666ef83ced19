// Must-show 2 of issue 45 (reference half): the AO tracer over an instanced forest and over the
// same forest written as copies gives the same bits for the same seed.
//
// Why the bits can agree: the G-buffer is bit-identical (scenes/instances_test.cpp), so every ray
// has the same origin and direction in both scenes. With falloff none an occlusion ray's value is
// binary, and Embree's robust (watertight) test decides hit or miss the same way in the prototype's
// space as in world space except for a ray that passes within float rounding of a triangle's edge
// or ends within rounding of a triangle (tfar = dmax); such a ray would flip one sample, 1/spp of
// a pixel. With a falloff the value depends on the hit distance, which instance traversal computes
// from the ray in the prototype's space: it agrees with the copy's only to a few ulps of t, so that
// definition is held to the bound |d value| <= |rho'| * 32 ulp(t) / dmax per ray, not to bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "base/testing/test_temp_dir.h"
#include "sampling/ao_tracer.h"
#include "scenes/instances.h"
#include "scenes/testing_forest.h"

namespace aoeval {
namespace {

template <class T>
size_t differing(const std::vector<T>& a, const std::vector<T>& b) {
  size_t n = 0;
  for (size_t k = 0; k < a.size(); ++k) n += std::memcmp(&a[k], &b[k], sizeof(T)) != 0;
  return a.size() == b.size() ? n : a.size() + b.size();
}

struct Pair {
  TracedAo instanced, copies;
};

Pair trace_both(const AoTraceSettings& settings, bool terrain = false) {
  const Scene s = load_scene_file(testutil::write_small_forest(
      testutil::test_temp_dir(terrain ? "forest-terrain" : "forest"), terrain));
  const Scene copies = scene_as_copies(s);
  const EmbreeScene a(s), b(copies);
  Pair p;
  for (const View& v : s.views) {
    const Camera cam = make_camera(v, 0, 0);
    const GBuffer ga = render_gbuffer(a, cam), gb = render_gbuffer(b, cam);
    TracedAo ta = trace_ao(a, ga, settings), tb = trace_ao(b, gb, settings);
    auto append = [](TracedAo& to, const TracedAo& from) {
      to.ao.insert(to.ao.end(), from.ao.begin(), from.ao.end());
      to.stderr_ao.insert(to.stderr_ao.end(), from.stderr_ao.begin(), from.stderr_ao.end());
      to.bent.insert(to.bent.end(), from.bent.begin(), from.bent.end());
      to.coverage.insert(to.coverage.end(), from.coverage.begin(), from.coverage.end());
      to.rays_traced += from.rays_traced;
    };
    append(p.instanced, ta);
    append(p.copies, tb);
  }
  return p;
}

TEST(InstancedTrace, ReferenceBitsEqualCopiesUnboundedCosine) {
  AoTraceSettings s;
  s.spp = 64;
  s.seed = 11;
  const Pair p = trace_both(s);
  EXPECT_GT(p.instanced.rays_traced, 100000u);
  EXPECT_EQ(p.instanced.rays_traced, p.copies.rays_traced);
  EXPECT_EQ(differing(p.instanced.ao, p.copies.ao), 0u);
  EXPECT_EQ(differing(p.instanced.stderr_ao, p.copies.stderr_ao), 0u);
  EXPECT_EQ(differing(p.instanced.bent, p.copies.bent), 0u);
  // Not a trivially open scene: the trees occlude.
  double mean = 0.0;
  size_t covered = 0;
  for (size_t k = 0; k < p.instanced.ao.size(); ++k)
    if (p.instanced.coverage[k] > 0.5f) mean += p.instanced.ao[k], ++covered;
  EXPECT_LT(mean / static_cast<double>(covered), 0.95);
}

TEST(InstancedTrace, ReferenceBitsEqualCopiesOnTerrain) {
  // The same forest standing "on" a sloping noise terrain: the lifted placements are the copies'.
  AoTraceSettings s;
  s.spp = 64;
  s.seed = 13;
  const Pair p = trace_both(s, true);
  EXPECT_GT(p.instanced.rays_traced, 100000u);
  EXPECT_EQ(differing(p.instanced.ao, p.copies.ao), 0u);
  EXPECT_EQ(differing(p.instanced.bent, p.copies.bent), 0u);
}

TEST(InstancedTrace, ReferenceBitsEqualCopiesBoundedNoFalloff) {
  AoTraceSettings s;
  s.spp = 32;
  s.seed = 3;
  s.sampler = SamplerKind::random;
  s.definition.weighting = Weighting::uniform;
  s.definition.dmax = 1.5;
  const Pair p = trace_both(s);
  EXPECT_EQ(differing(p.instanced.ao, p.copies.ao), 0u);
  EXPECT_EQ(differing(p.instanced.bent, p.copies.bent), 0u);
}

TEST(InstancedTrace, ReferenceWithFalloffWithinDistanceRounding) {
  AoTraceSettings s;
  s.spp = 32;
  s.seed = 5;
  s.definition.dmax = 2.0;
  s.definition.falloff = Falloff::linear;
  const Pair p = trace_both(s);
  // rho(x) = x: a ray's value moves by |d t| / dmax; t < dmax = 2 has ulp <= 2^-22, and 32 of
  // them bound the difference of the two traversals' distances (the prototype-space ray of a
  // scaled, rotated instance rounds its origin and direction once more, and the hit distance
  // inherits those roundings times the triangle's conditioning). The pixel mean moves no more.
  // Measured on the small forest: 5.4e-7 at most (about 4.5 ulps).
  const double bound = 32.0 * std::ldexp(1.0, -22) / 2.0;
  double worst = 0.0;
  for (size_t k = 0; k < p.instanced.ao.size(); ++k)
    worst = std::max(worst, std::fabs(static_cast<double>(p.instanced.ao[k]) - p.copies.ao[k]));
  EXPECT_LE(worst, bound);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("max_abs_difference", text);
}

}  // namespace
}  // namespace aoeval
