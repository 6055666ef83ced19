// hbao-split, hbao-split-cpu: Dimitrov, Bavoil, Sainz 2008, "Horizon-Split Ambient Occlusion".
// Implements horizon tracing (§3.1, Fig. 4), the closed-form horizon occlusion T(theta) = H^2
// (eq. 3-6, §3.2), normal occlusion with the cosine patch distribution (eq. 7-12, §3.3), their
// combination A = 1 - (O_T + O_N) (§3.4), linear attenuation (§3.5), the offset against banding
// (eq. 13, §4.1.1), the tiled randomisation texture (§4.1.2) and the depth-aware 5x5 blur (§4.1.3).
//
// The per-pixel algorithm is one source, hbao_kernel.glsl, compiled as C++ for the CPU twin
// (hbao-split-cpu, TBB over rows) and as GLSL for the Vulkan twin (hbao-split); both read the same
// eye-space depth and normals, the same random texture bits generated here and the same direction
// table, so they agree to 1e-3 (hbao_split_test.cpp). resolution = half runs the passes on the
// half-resolution frame and upsamples the AO with the shared joint bilateral filter
// (screen_space/half_res.h). Declared AO definition: cosine weighting, dmax = R, linear falloff
// when attenuation is on (none otherwise).
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/screen_space/frame.h"
#include "estimators/temporal/temporal_stage.h"

namespace aoeval {
namespace hbao_glsl {
#include "estimators/hbao_split/hbao_constants.glsl"
}  // namespace hbao_glsl
using hbao_glsl::HbaoConstants;

// Defaults: Fig. 11 (c) of the paper (R = 0.3 with linear attenuation, Nd = 8, Ns = 18, Nn = 1),
// the middle of its quality range; its quality preset is Nd = 18, Ns = 25, Nn = 2 (Fig. 11 (d)).
struct HbaoSettings {
  // No defaults here: the parameter table declares them once; hbao_settings_of fills this from a
  // ParamSet (default_params(...) for "every parameter at its default").
  double radius;    // R
  int directions;   // Nd
  int steps;        // Ns
  int normal_rays;  // Nn (0 disables normal occlusion)
  bool attenuation;
  bool offset;
  bool jitter;
  int tile;
  bool blur;
  uint64_t seed;
  bool half_res;  // resolution = half (screen_space/half_res.h)
  bool temporal;  // accumulate a sequence's frames with the shared temporal stage
  TemporalSettings temporal_stage;
  // Not a parameter: the sequence frame whose random texture this is, the seed rule's k
  // (FrameInfo::seed_offset; 0 for a still view and when the run keeps one seed): the texture of
  // frame k is drawn from seed + k, so the per-pixel rotation advances every frame.
  uint64_t frame = 0;
};

// What a row records about the time design (FrameDeviceEstimator::derived): nothing; the texture
// of frame k is the still texture of seed + k, so a still view is frame 0 and says nothing new.
inline nlohmann::json frame_derived(const HbaoSettings&, bool /*still*/) {
  return nlohmann::json::object();
}

// The parameter table shared by both twins (hbao-split adds `gbuffer`).
std::vector<ParamSpec> hbao_param_specs();
HbaoSettings hbao_settings_of(const ParamSet& params);
// The twin as it runs a sequence: itself, or wrapped in the temporal stage when `temporal` is on
// (temporal_estimator.h; the stage's output at frame 0 and at a still view is the twin's own).
std::unique_ptr<Estimator> hbao_over_time(std::unique_ptr<Estimator> twin,
                                          const HbaoSettings& settings);
// Cosine weighting, dmax = R, linear falloff with attenuation, none without.
AoDefinition hbao_definition(const HbaoSettings& settings);
extern const char* const kHbaoPaper;
extern const char* const kHbaoDefinitionDoc;

// §4.1.2: tile x tile texels of (cos alpha, sin alpha, beta), alpha uniform in [0, 2 pi / Nd), beta
// uniform in (-1, 1), from `seed` + `frame`; all (1, 0, 0) without jitter. Row-major, texel (i mod
// tile, j mod tile) serves pixel (i, j).
std::vector<glm::vec3> hbao_random_texture(const HbaoSettings& settings);
// (cos, sin) of 2 pi d / Nd, d < Nd, evaluated in double and rounded.
std::vector<glm::vec2> hbao_direction_table(int directions);
// The compute shaders' workgroup side (local_size_x = local_size_y in every hbao shader).
inline constexpr int kHbaoGroupSize = 8;
// The constants for a frame of `shape`'s size, focal length and principal point (pixels unread).
HbaoConstants hbao_constants(const HbaoSettings& settings, const ScreenSpaceFrame& shape);

// Checks what the parameter table cannot (a frame to work on); InputError otherwise.
void validate_hbao_frame(const ScreenSpaceFrame& frame);
// Max |a - b| over the frame's covered pixels (depth > 0): how far two AO images of the frame
// differ, e.g. the twins' (the bench and the twin tests).
double hbao_max_abs_difference(const ScreenSpaceFrame& frame, const std::vector<float>& a,
                               const std::vector<float>& b);

struct HbaoCpuResult {
  std::vector<float> ao;          // final AO (blurred when settings.blur), 0 where not covered
  std::vector<float> raw_ao;      // before the blur (half-size with resolution = half)
  std::vector<float> horizon_ao;  // 1 - O_T: horizon occlusion alone (the paper's Fig. 10 (a))
  uint64_t depth_fetches = 0;     // fetches by the linear searches (counted only when asked)
  double horizon_ms = 0.0, normal_ms = 0.0, blur_ms = 0.0;  // wall time of each pass
  double downsample_ms = 0.0, upsample_ms = 0.0;            // resolution = half only
};

// The CPU twin. Deterministic: same inputs, same bits, whatever the thread count.
HbaoCpuResult hbao_split_cpu(const ScreenSpaceFrame& frame, const HbaoSettings& settings,
                             bool count_fetches = false);

EstimatorInfo hbao_split_cpu_estimator();

}  // namespace aoeval
