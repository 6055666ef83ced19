// Analytic scenes for the screen-space estimators' tests (hbao-split, raymarch-ssao): a floor seen
// at grazing angles, and a crease (floor meeting a tall wall) whose horizon-split AO has a closed
// form that is also the exact AO of the bounded definition.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scenes/analytic_scenes.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"

namespace aoeval {

// A rendered test view: the scene, its Embree scene and the shared G-buffer.
struct TestView {
  Scene scene;
  std::unique_ptr<EmbreeScene> embree;
  GBuffer gbuffer;
};

inline TestView render_view(Scene scene, const View& view, int width, int height) {
  TestView t;
  t.scene = std::move(scene);
  t.scene.views = {view};
  t.embree = std::make_unique<EmbreeScene>(t.scene);
  t.gbuffer = render_gbuffer(*t.embree, make_camera(view, width, height));
  return t;
}

// A 60 x 60 floor (y = 0, facing +Y) seen from height 1, the view axis 55 degrees from the normal
// and a 60 degree vertical field: the pixels' view rays meet the floor 25 to 85 degrees from its
// normal.
inline TestView grazing_floor(int width, int height) {
  View v;
  v.eye = glm::vec3(0.0f, 1.0f, 0.0f);
  const float axis = 55.0f * std::numbers::pi_v<float> / 180.0f;
  v.target = glm::vec3(0.0f, 1.0f - std::cos(axis), -std::sin(axis));
  v.fov_y_deg = 60.0f;
  return render_view(scene_of({generated("floor", "plane", {{"size", {60, 60}}})}), v, width,
                     height);
}

// The angle between pixel k's view ray and the surface normal, degrees.
inline double view_angle_deg(const GBuffer& g, int i, int j) {
  const glm::vec3 d = g.camera.direction(i, j);
  const double c = std::abs(glm::dot(d, g.normal[g.index(i, j)]));
  return std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi;
}

// The crease: the inside of a 4 x 2 x 4 box with only its floor (y = 0) and its back wall
// (z = -2) kept, seen from above and in front.
inline TestView crease(int width, int height) {
  View v;
  v.eye = glm::vec3(0.0f, 1.2f, 0.2f);
  v.target = glm::vec3(0.0f, 0.0f, -1.7f);
  v.fov_y_deg = 60.0f;
  const nlohmann::json params = {
      {"size", {4, 2, 4}}, {"inward", true}, {"open", {"+y", "+x", "-x", "+z"}}};
  return render_view(scene_of({generated("crease", "box", params)}), v, width, height);
}

constexpr float kCreaseWallZ = -2.0f;

// Exact AO (cosine weighting, dmax = R) of a floor point at distance x from a wall taller than R:
// in direction theta (0 = towards the wall) the wall lies at d = x / cos(theta); the directions
// that hit it within R have sin(elevation)^2 = u in [0, 1 - (d/R)^2], where the hit lies at
// r = d / sqrt(1 - u). Cosine-weighted, each direction contributes T = Int W(r) du over that range
// (/ 2 pi over theta), which is also the horizon-split value (T = H^2 without attenuation,
// H^2 = 1 - (d/R)^2; with W = 1 - r/R, T = (1 - d/R)^2). Zero for |theta| >= acos(x / R).
inline double crease_ao(double x, double radius, bool attenuation) {
  const double a = x / radius;
  if (a >= 1.0) return 1.0;
  const double theta0 = std::acos(a);
  const int n = 4000;  // midpoint rule; the integrand is smooth inside (-theta0, theta0)
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double theta = -theta0 + (k + 0.5) * (2.0 * theta0 / n);
    const double ad = a / std::cos(theta);
    sum += attenuation ? (1.0 - ad) * (1.0 - ad) : 1.0 - ad * ad;
  }
  const double occlusion = sum * (2.0 * theta0 / n) / (2.0 * std::numbers::pi);
  return 1.0 - occlusion;
}

// Pixels of the crease's floor at least `margin` from the wall's side ends (the wall spans
// x in [-2, 2]), with their distance to the wall.
struct CreasePixel {
  size_t k;
  double x;
};
inline std::vector<CreasePixel> crease_floor_pixels(const GBuffer& g, double margin) {
  std::vector<CreasePixel> out;
  for (size_t k = 0; k < g.pixel_count(); ++k) {
    if (!g.covered(k) || g.normal[k].y < 0.99f) continue;
    if (std::abs(g.position[k].x) > 2.0f - margin) continue;
    out.push_back({k, static_cast<double>(g.position[k].z - kCreaseWallZ)});
  }
  return out;
}

// An AO image against crease_ao over the crease's floor pixels: how many lie within R of the wall
// (closed form below 0.999), and the bias, mean absolute, root-mean-square and largest absolute
// error.
struct CreaseErrors {
  size_t within_radius = 0;
  double bias = 0.0, mean_abs = 0.0, rms = 0.0, max_abs = 0.0;
};
inline CreaseErrors crease_errors(const std::vector<float>& ao,
                                  const std::vector<CreasePixel>& pixels, double radius,
                                  bool attenuation) {
  CreaseErrors e;
  for (const CreasePixel& p : pixels) {
    const double expected = crease_ao(p.x, radius, attenuation);
    const double error = ao[p.k] - expected;
    if (expected < 0.999) ++e.within_radius;
    e.bias += error;
    e.mean_abs += std::abs(error);
    e.rms += error * error;
    e.max_abs = std::max(e.max_abs, std::abs(error));
  }
  const double n = static_cast<double>(std::max<size_t>(1, pixels.size()));
  e.bias /= n;
  e.mean_abs /= n;
  e.rms = std::sqrt(e.rms / n);
  return e;
}

}  // namespace aoeval
