// hbao-split's parameter table (declared once for both twins) and the host-side inputs of the
// kernel: eye-space depth and normals, the tiled random texture (§4.1.2), the direction table and
// the constants. See hbao_split.h.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "base/errors.h"
#include "estimators/hbao_split/hbao_split.h"
#include "estimators/screen_space/half_res.h"
#include "estimators/seed_param.h"
#include "estimators/temporal/temporal_estimator.h"
#include "scenes/random.h"

namespace aoeval {

const char* const kHbaoPaper =
    "Dimitrov, Bavoil, Sainz 2008, Horizon-Split Ambient Occlusion: horizon tracing (§3.1, Fig. "
    "4), "
    "horizon occlusion T = H^2 in closed form (eq. 3-6), normal occlusion with the cosine patch "
    "distribution (eq. 7-12, patches starting at the horizon), A = 1 - (O_T + O_N) (§3.4), linear "
    "attenuation (§3.5), offset P' = P + z/(f res) n (eq. 13), tiled random texture (§4.1.2), "
    "depth-aware 5x5 blur (§4.1.3)";

const char* const kHbaoDefinitionDoc =
    "cosine weighting (eq. 1), dmax = R, falloff linear when attenuation is on (an occluder at "
    "distance r < R counts 1 - r/R, §3.5), none when off; only what the depth buffer shows within "
    "R of P' can occlude";

// The temporal stage's defaults for hbao-split (temporal_stage.h), which apply when `temporal` is
// turned on: its per-frame noise is the random texture's rotation after the 5x5 blur, small beside
// gtao's one slice, so a history of 16 frames averages it. `temporal` itself stays off by default:
// `aoeval tune harness/tune/specs/tune-hbao-split-motion.json` (lag_rmse_excess +
// steady_rmse_excess over rolling-ball/roll, dragon/walk and bunny/orbit, 128x96) scored no
// history 0.1035 (its run with `temporal` free, 64 evaluations; no history runs no stage) and
// the best temporal point 0.1238. The clamp and the anti-lag are that tune's best (issue 43,
// h43i: `temporal` fixed on, 32 evaluations over clamp, antilag, antilag_min, antilag_radius and
// antilag_frames, with the anti-lag's test that takes in the history's noise): clamp on, antilag
// 3.15, antilag_min 0, a 5x5 window, a 2-frame fast history (clamp off: 0.1259; the defaults
// before, no clamp and no anti-lag: 0.1622).
// At 320x240 (harness/specs/temporal-lag-table-320.json, 64-spp references) they take
// lag_rmse_excess from 0.1753 to 0.0638 on roll and 0.2009 to 0.0935 on walk, and steady
// rmse_excess on bunny/still 0.01942 -> 0.01966 and tree-ground/still 0.07658 -> 0.07497.
TemporalDefaults hbao_temporal_defaults() {
  return {.history_limit = 16,
          .alpha_min = 0.0,
          .clamp = true,
          .gamma = 1.0,
          .clamp_sigma_min = 0.1,
          .clamp_radius = 1,
          .antilag = 3.15,
          .antilag_min = 0.0,
          .antilag_radius = 2,
          .antilag_frames = 2};
}

std::vector<ParamSpec> hbao_param_specs() {
  std::vector<ParamSpec> params = {
      real_param(
          {.name = "R",
           .def = 0.3,
           .min = 1e-4,
           .max = 1e4,
           .spacing = Spacing::log,
           .unit = "scene units",
           .meaning =
               "radius of influence: horizon and normal rays stop at distance R (§3.1, §3.6; "
               "Fig. 6, 11)"}),
      int_param({.name = "Nd",
                 .def = 8,
                 .min = 1,
                 .max = 64,
                 .spacing = Spacing::linear,
                 .unit = "directions",
                 .meaning = "horizon directions theta around the normal, each a lune of 2 pi / Nd "
                            "(§3.1, eq. 5-6)"}),
      int_param({.name = "Ns",
                 .def = 18,
                 .min = 1,
                 .max = 256,
                 .spacing = Spacing::linear,
                 .unit = "steps",
                 .meaning = "steps of R / Ns per horizon and normal ray (Fig. 4 line 2, §3.6)"}),
      int_param({.name = "Nn",
                 .def = 1,
                 .min = 0,
                 .max = 16,
                 .spacing = Spacing::linear,
                 .unit = "rays",
                 .meaning =
                     "normal-occlusion rays per direction above the horizon, 0 disables O_N (§3.3, "
                     "eq. 7-12)"}),
      bool_param({.name = "attenuation",
                  .def = true,
                  .meaning = "weight each occluder at distance r by 1 - r/R (§3.5); the "
                             "definition's linear falloff"}),
      bool_param({.name = "offset",
                  .def = true,
                  .meaning = "start rays at P' = P + z/(f res) n against banding at grazing angles "
                             "(eq. 13, §4.1.1)"}),
      bool_param({.name = "jitter",
                  .def = true,
                  .meaning = "per-pixel rotation alpha and step jitter beta from the tiled random "
                             "texture (§4.1.2)"}),
      int_param(
          {.name = "tile",
           .def = 4,
           .min = 1,
           .max = 64,
           .spacing = Spacing::linear,
           .unit = "pixels",
           .meaning = "side of the tiled random texture of (cos alpha, sin alpha, beta) (§4.1.2)"}),
      bool_param(
          {.name = "blur",
           .def = true,
           .meaning =
               "5x5 Gaussian weighted by the inverse depth deviation from the centre (§4.1.3)"}),
      seed_param("seed of the random texture (§4.1.2); frame k of a sequence draws it "
                 "from seed + k"),
      resolution_param(),
      bool_param(
          {.name = "temporal",
           .def = false,
           .meaning =
               "accumulate the frames of a sequence (each with the random texture of seed + k) "
               "with the shared temporal stage (estimators/temporal/): reprojection, "
               "disocclusion reset, exponential history, clamp, anti-lag; false = each frame its "
               "own estimate. "
               "A still view is frame 0 either way"}),
  };
  // The stage's own parameters, read only when temporal is on (temporal_stage.h).
  for (ParamSpec& p : temporal_params(hbao_temporal_defaults())) params.push_back(std::move(p));
  return params;
}

HbaoSettings hbao_settings_of(const ParamSet& p) {
  HbaoSettings s{};
  s.radius = p.real("R");
  s.directions = static_cast<int>(p.integer("Nd"));
  s.steps = static_cast<int>(p.integer("Ns"));
  s.normal_rays = static_cast<int>(p.integer("Nn"));
  s.attenuation = p.boolean("attenuation");
  s.offset = p.boolean("offset");
  s.jitter = p.boolean("jitter");
  s.tile = static_cast<int>(p.integer("tile"));
  s.blur = p.boolean("blur");
  s.seed = static_cast<uint64_t>(p.integer("seed"));
  s.half_res = half_resolution(p);
  s.temporal = p.boolean("temporal");
  s.temporal_stage = temporal_settings(p);
  return s;
}

std::unique_ptr<Estimator> hbao_over_time(std::unique_ptr<Estimator> twin,
                                          const HbaoSettings& settings) {
  if (!settings.temporal) return twin;
  return with_temporal_stage(std::move(twin), settings.temporal_stage);
}

AoDefinition hbao_definition(const HbaoSettings& s) {
  AoDefinition d;
  d.weighting = Weighting::cosine;
  d.dmax = s.radius;
  d.falloff = s.attenuation ? Falloff::linear : Falloff::none;
  return d;
}

std::vector<glm::vec3> hbao_random_texture(const HbaoSettings& s) {
  const size_t texels = static_cast<size_t>(s.tile) * static_cast<size_t>(s.tile);
  std::vector<glm::vec3> texture(texels, glm::vec3(1.0f, 0.0f, 0.0f));
  if (!s.jitter) return texture;
  const double sector = 2.0 * std::numbers::pi / s.directions;
  for (size_t k = 0; k < texels; ++k) {
    SplitMix64 rng(mix_seed(s.seed + s.frame, k, 0x4842414F));  // "HBAO"; the seed rule
    const double alpha = rng.uniform_double() * sector;
    // (u + 0.5) / 2^24 lies strictly inside (0, 1), so beta = 2u - 1 lies inside (-1, 1).
    const double u = (static_cast<double>(rng.next() >> 40) + 0.5) / 16777216.0;
    texture[k] = glm::vec3(static_cast<float>(std::cos(alpha)), static_cast<float>(std::sin(alpha)),
                           static_cast<float>(2.0 * u - 1.0));
  }
  return texture;
}

std::vector<glm::vec2> hbao_direction_table(int directions) {
  std::vector<glm::vec2> table(static_cast<size_t>(directions));
  for (int d = 0; d < directions; ++d) {
    const double theta = 2.0 * std::numbers::pi * d / directions;
    table[static_cast<size_t>(d)] =
        glm::vec2(static_cast<float>(std::cos(theta)), static_cast<float>(std::sin(theta)));
  }
  return table;
}

HbaoConstants hbao_constants(const HbaoSettings& s, const ScreenSpaceFrame& shape) {
  const int width = shape.width, height = shape.height;
  const float focal = shape.focal;
  HbaoConstants c{};
  c.radius = static_cast<float>(s.radius);
  c.step = static_cast<float>(s.radius / s.steps);
  c.focal = focal;
  c.half_width = 0.5f * static_cast<float>(width) + shape.centre_shift.x;
  c.half_height = 0.5f * static_cast<float>(height) + shape.centre_shift.y;
  // eq. 13: the staircase step at depth z is z / (f res) with f = 1 / tan(fov/2) and res the
  // pixels across the (square-pixel) screen height: 1 / (f res) = tan(fov/2) / H = 1 / (2 focal).
  c.offset_scale = s.offset ? 0.5f / focal : 0.0f;
  c.width = width;
  c.height = height;
  c.directions = s.directions;
  c.steps = s.steps;
  c.normal_rays = s.normal_rays;
  c.attenuation = s.attenuation ? 1 : 0;
  c.tile = s.tile;
  c.row_stride = workgroup_row_stride((height + kHbaoGroupSize - 1) / kHbaoGroupSize);
  return c;
}

void validate_hbao_frame(const ScreenSpaceFrame& f) {
  if (f.width < 1 || f.height < 1)
    throw InputError("hbao-split: the G-buffer is empty (" + std::to_string(f.width) + "x" +
                     std::to_string(f.height) + ")");
  if (!(f.focal > 0.0f) || !std::isfinite(f.focal))
    throw InputError("hbao-split: the camera's field of view gives no finite focal length");
}

double hbao_max_abs_difference(const ScreenSpaceFrame& f, const std::vector<float>& a,
                               const std::vector<float>& b) {
  double m = 0.0;
  for (size_t k = 0; k < f.depth.size(); ++k)
    if (f.depth[k] > 0.0f) m = std::max(m, std::abs(static_cast<double>(a[k]) - b[k]));
  return m;
}

}  // namespace aoeval
