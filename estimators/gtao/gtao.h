// gtao, gtao-cpu: Jimenez, Wu, Pesce, Jarabo 2016, "Practical Real-Time Strategies for Accurate
// Indirect Occlusion" (ground-truth ambient occlusion, GTAO). Implements the cosine-weighted AO
// integral in view-aligned slices (the paper's eq. 1-3), the projected normal (eq. 4-6), horizon
// search per side with the radius and a linear falloff of the horizon, clamped to the normal's
// hemisphere (eq. 7-8), the closed-form inner integral "a^" (eq. 10), the bent normal extension
// (the cosine-weighted mean unoccluded direction, the paper's Algorithm 2), a polynomial arccosine
// (§5), the thin-occluder (thickness) heuristic, a final power and the spatial 4 x 4 denoise of the
// per-pixel slice rotation noise (§5.2). The multi-bounce approximation is not part of AO and is
// left out. The formulas, and which are ours, are in gtao_kernel.glsl.
//
// Over time (§5.2's temporal half): `rotations` makes the slice rotation and the sample offset
// advance every frame (gtao_noise_of: the paper's 6 rotations x 4 offsets on top of the 4 x 4
// spatial noise). Both twins keep state over a sequence (they read the frame index themselves); a
// still view is frame 0, which is the still estimate bit for bit, and its row says so
// (frame_derived). The paper's accumulation of the rotated frames (the shared temporal stage of
// issue 31): with `temporal` on, both twins feed each frame's final AO through the shared temporal
// stage (estimators/temporal/temporal_estimator.h: reprojection, disocclusion reset, exponential
// history, neighbourhood clamp), so 1 slice with 6 rotations accumulates towards many slices;
// off (the default), each frame is its own estimate.
//
// The per-pixel algorithm is one source, gtao_kernel.glsl, compiled as C++ for the CPU twin
// (gtao-cpu, TBB over rows) and as GLSL for the Vulkan twin (gtao); both read the same eye-space
// depth and normals (the screen-space frame, estimators/screen_space/frame.h), the same noise and
// step tables made here, and apply the final power and the world-space bent normal on the host
// with the same code, so they agree bit for bit where the device rounds like IEEE 754
// (gtao_test.cpp).
//
// resolution = half runs both twins' passes on the half-resolution frame and upsamples the AO and
// bent normals with the shared joint bilateral filter (estimators/screen_space/half_res.h).
//
// Declared AO definition: cosine weighting (eq. 1), dmax = R; falloff none when the falloff range
// is 0 (an occluder counts fully within R: the horizon is the highest point seen within R), linear
// otherwise (approximate: GTAO fades the horizon's cosine towards the tangent plane between
// (1 - falloff) R and R, not the occlusion of each direction). What the depth buffer hides (behind
// the first surface, outside the screen) does not occlude, and each slice's visible set is taken
// to be the arc above its two horizons.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <string>
#include <vector>

#include "estimators/estimator.h"
#include "estimators/screen_space/frame.h"
#include "estimators/temporal/temporal_stage.h"
#include "scenes/camera.h"

namespace aoeval {
namespace gtao_glsl {
#include "estimators/gtao/gtao_constants.glsl"
}  // namespace gtao_glsl
using gtao_glsl::GtaoConstants;

// Filled from the parameter table (gtao_param_specs), which holds every default.
struct GtaoSettings {
  double radius;
  int slices;
  int steps;
  double falloff;
  double power;
  double thickness;
  double final_power;
  bool normalise;
  bool bent;
  bool denoise;
  bool jitter;
  int tile;
  uint64_t seed;
  bool half_res;  // resolution = half (half_res.h)
  int rotations;  // the temporal noise schedule (gtao_noise_of)
  bool temporal;  // accumulate a sequence's frames with the shared temporal stage
  TemporalSettings temporal_stage;
  // Not a parameter: the sequence frame whose noise the tables hold, the seed rule's k
  // (FrameInfo::seed_offset; 0 for a still view and when the run keeps one seed).
  uint64_t frame = 0;
};

// The parameter table shared by both twins (gtao adds `gbuffer`).
std::vector<ParamSpec> gtao_param_specs();
GtaoSettings gtao_settings_of(const ParamSet& params);
AoDefinition gtao_definition(const GtaoSettings& settings);
extern const char* const kGtaoPaper;
extern const char* const kGtaoDefinitionDoc;

// The noise of frame `settings.frame` over a sequence (the paper's §5.2: spatial 4 x 4 noise and 6
// temporal rotations). rotations = 1: each frame draws its own noise texture, from seed + k (the
// seed rule every stochastic estimator follows, CONTRACT §10). rotations = N > 1: one texture
// (seed) whose slice rotation advances by a rotation of j / N of the slice spacing pi / slices at
// frame k, j = the k mod N-th entry of the schedule (for N = 6 the paper's 60, 300, 180, 240, 120,
// 0 degrees read as sixths of the spacing, started at its 0 entry; otherwise the radical-inverse
// order of 0..N-1, which spreads any run of consecutive frames evenly), and whose sample offset
// advances by the paper's 0, 1/2, 1/4, 3/4 of a step every N frames (a period of 4 N frames). Frame
// 0 is the still frame under every schedule.
struct GtaoNoise {
  uint64_t seed = 0;      // of the noise texture
  double rotation = 0.0;  // added to each texel's rotation, a fraction of the slice spacing
  double offset = 0.0;    // added to each texel's sample offset, a fraction of a step
};
GtaoNoise gtao_noise_of(const GtaoSettings& settings);
// The j of frame k's rotation j / N (the schedule above), for tests and figures.
int gtao_rotation_index(uint64_t frame, int rotations);
// What a row records about the schedule (the twins' derived()): with rotations > 1, "rotations"
// says a still view is frame 0 of the schedule, and a sequence which frames repeat; nothing with
// rotations = 1 (frame k is then the still estimate of seed + k, as for any stochastic built-in).
nlohmann::json frame_derived(const GtaoSettings& settings, bool still);
// A twin as created, accumulated by the shared temporal stage when settings.temporal (else as is).
std::unique_ptr<Estimator> gtao_over_time(std::unique_ptr<Estimator> twin,
                                          const GtaoSettings& settings);
extern const char* const kGtaoStillFrameNote;

// The host-made inputs of the kernel. rotation: tile x tile texels (cos a, sin a), a uniform in
// [0, pi / slices) from `seed` (a = pi / (2 slices), the middle, without jitter); steps: for each
// texel, `steps` sample distances ((k + u) / steps)^power, u uniform in [0, 1) (1/2 without
// jitter); slices: (cos, sin) of pi s / slices. All evaluated in double and rounded. Over a
// sequence a and u are those of frame settings.frame's noise (gtao_noise_of), wrapped into [0, 1).
struct GtaoTables {
  std::vector<glm::vec2> rotation;
  std::vector<float> steps;
  std::vector<glm::vec2> slices;
};
GtaoTables gtao_tables(const GtaoSettings& settings);
// The workgroup side of the compute shaders (local_size_x = local_size_y).
inline constexpr int kGtaoGroupSize = 8;
// The constants for a frame of `shape`'s size, focal length and principal point (pixels unread).
GtaoConstants gtao_constants(const GtaoSettings& settings, const ScreenSpaceFrame& shape);
// Checks what the parameter table cannot (a frame of at least 2 x 2 pixels with a finite focal
// length); InputError otherwise.
void validate_gtao_frame(const ScreenSpaceFrame& frame);

struct GtaoOutput {
  std::vector<float> ao;        // final AO (denoised, then ^final_power), 0 where not covered
  std::vector<float> raw_ao;    // before the denoise pass and the power (half-size at half res)
  std::vector<glm::vec3> bent;  // unit world-space bent normal, 0 where none (bent on only)
  std::map<std::string, double> pass_ms;
};

// What both twins do after the kernel, on the host with one piece of code: the final power
// AO^final_power and the bent normals from eye space (camera right, up, forward) to world space.
void gtao_finish(const GtaoSettings& settings, const Camera& camera, const ScreenSpaceFrame& frame,
                 std::vector<float>& ao, const std::vector<glm::vec3>& eye_bent, GtaoOutput& out);

// The CPU twin. Deterministic: same inputs, same bits, whatever the thread count. The camera only
// orients the bent normals in world space.
GtaoOutput gtao_cpu(const ScreenSpaceFrame& frame, const Camera& camera,
                    const GtaoSettings& settings);

// The estimate's channels: AO, and bent.X/Y/Z when settings.bent.
EstimateResult gtao_estimate_result(const GtaoSettings& settings, GtaoOutput output);

EstimatorInfo gtao_cpu_estimator();
EstimatorInfo gtao_estimator();

}  // namespace aoeval
