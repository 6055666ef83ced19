// The engine teams' questions (issue 32), answered as figures with checks: `half-resolution`
// (gtao and hbao-split at full and half resolution, error split into depth-edge and interior
// pixels, and time) and `gtao-thickness` (gtao's thin-occluder thickness on thin and thick scenes,
// and whether one default serves both). The checks are functions of the numbers, so that a test
// can feed them numbers on both sides of each rule (figures_engine_test.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "harness/figures/figure.h"
#include "scenes/gbuffer.h"

namespace aoeval::figures {

// The depth-edge pixels of a G-buffer: covered pixels p with a pixel q within kEdgeRadius (the
// Chebyshev distance, inside the image) that is uncovered or whose linear depth differs from p's by
// more than kEdgeDepthJump times the larger of the two. The radius covers the half-resolution
// upsample's reach (its samples lie up to one full pixel away) plus the half-resolution kernels'
// own footprint of one half pixel; the jump is the upsample's depth tolerance (half_res.glsl),
// which no floor seen up to ~85 degrees from its normal reaches between neighbours.
inline constexpr int kEdgeRadius = 2;
inline constexpr float kEdgeDepthJump = 0.05f;
std::vector<uint8_t> depth_edge_mask(const GBuffer& g);

// half-resolution: per estimator and scene, RMSE excess (reference noise removed) at full and half
// resolution on edge and interior pixels; per estimator, interleaved AO times at both.
struct HalfResScore {
  std::string estimator, scene;
  double full_edge = 0.0, half_edge = 0.0, full_interior = 0.0, half_interior = 0.0;
};
struct HalfResTimes {
  std::string estimator;
  std::vector<double> full_ms, half_ms;  // per interleaved round
};
struct HalfResNumbers {
  std::vector<HalfResScore> scores;
  std::vector<HalfResTimes> times;
};
std::vector<Check> half_resolution_checks(const HalfResNumbers& n);

// gtao-thickness: rmse_excess per scene (thin ones first) per thickness, and the declared default.
struct ThicknessNumbers {
  std::vector<double> thickness;           // the grid, ascending, starting at 0
  std::vector<std::string> scenes;         // thin scenes, then thick ones
  std::vector<bool> thin;                  // per scene
  std::vector<std::vector<double>> error;  // [scene][thickness]
  double declared_default = 0.0;           // gtao's table default
};
// The thickness that serves every scene best: the least worst ratio of a scene's error to its own
// best error over the grid (ties: the smaller thickness), and that worst ratio.
struct ThicknessChoice {
  double thickness = 0.0, worst_ratio = 0.0;
};
ThicknessChoice choose_thickness(const ThicknessNumbers& n);
std::vector<Check> gtao_thickness_checks(const ThicknessNumbers& n);

}  // namespace aoeval::figures
