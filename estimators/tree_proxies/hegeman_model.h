// The per-pixel closed forms of Hegeman, Premoze, Ashikhmin, Drettakis 2006, "Approximate Ambient
// Occlusion for Trees" (I3D '06), and the depth of Reeves and Blau 1985 as they describe it. Inline
// and allocation-free: the estimators call them once per pixel, the tests call them directly.
//
// All of them estimate uniform-weighted (eq. 3: (1/2pi) Int V dw), unbounded ambient visibility.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "scenes/scene.h"

namespace aoeval::hegeman {

constexpr float kPi = 3.14159265358979323846f;

// Eq. 4: volume of the spherical segment ("cap") of height h in [0, 2R] of a sphere of radius R.
// h = 2R gives the whole sphere (4/3 pi R^3), h = R a hemisphere (2/3 pi R^3).
inline float cap_volume(float h, float R) {
  return kPi / 3.0f * h * h * (3.0f * R - h);
}

// Eq. 5 from squared lengths: f = h^2 / (h^2 + d^2), the squared cosine of the "off-centre angle"
// seen from the cap's pole. f = 1 at the centre of the cutting disk (d = 0). Where h = d = 0 (a
// point on the boundary with its normal pointing out) the cap is empty and f is irrelevant; 1 then.
inline float off_center_factor(float h2, float d2) {
  const float s = h2 + d2;
  return s > 0.0f ? h2 / s : 1.0f;
}

// Fig. 1: the plane through x with unit normal n cuts the sphere (centre c, radius R); the cap is
// the part on n's side. t = (x - c).n is the centre's distance behind the plane, so the cap height
// is h = R - t (clamped: 0 when the plane misses the sphere in front, 2R when the whole sphere is
// in front), and d is x's distance from the disk centre c + t n, within the plane.
struct Cap {
  float h;   // cap height
  float d2;  // squared off-centre distance
};
inline Cap cap_geometry(const glm::vec3& x, const glm::vec3& n, const glm::vec3& c, float R) {
  const glm::vec3 q = x - c;
  const float t = glm::dot(q, n);
  return {std::clamp(R - t, 0.0f, 2.0f * R), std::max(0.0f, glm::dot(q, q) - t * t)};
}

// Eq. 6: V = exp(-alpha rho f V_cap) for a sphere.
inline float sphere_visibility(const glm::vec3& x, const glm::vec3& n, const glm::vec3& c, float R,
                               float alpha_rho) {
  const Cap k = cap_geometry(x, n, c, R);
  return std::exp(-alpha_rho * off_center_factor(k.h * k.h, k.d2) * cap_volume(k.h, R));
}

// §3, ellipsoids: "the same runtime computation is performed but only after corresponding scaling
// along the axes is applied, bringing the ellipsoidal shell into a sphere". The ellipsoid is
// {c + A u : |u| <= 1} with A = axes * diag(radii). Points map by u = A^-1 (x - c); the cutting
// plane n.(y - x) = 0 becomes (A^T n).(u - u_x) = 0, so normals map by A^T (the inverse-transpose
// of A^-1). In the unit sphere h, d and f are computed as for a sphere of radius 1; the cap's world
// volume is |det A| times its unit volume (an affine map scales every volume by |det A|), so
// alpha rho keeps its meaning (per world volume) and equal radii R give exactly eq. 4-6 in R.
struct UnitMap {
  glm::vec3 center{0.0f};
  glm::mat3 to_unit{1.0f};     // A^-1
  glm::mat3 normal_map{1.0f};  // A^T
  float det = 1.0f;            // |det A| = r1 r2 r3
  float min_radius = 1.0f;     // smallest semi-axis
  float max_radius = 1.0f;     // largest semi-axis
};
inline UnitMap make_unit_map(const Ellipsoid& e) {
  glm::mat3 a = e.axes;
  for (int k = 0; k < 3; ++k) a[k] *= e.radii[k];
  UnitMap m;
  m.center = e.center;
  m.to_unit = glm::inverse(a);
  m.normal_map = glm::transpose(a);
  m.det = std::fabs(glm::determinant(a));
  m.min_radius = std::min({e.radii.x, e.radii.y, e.radii.z});
  m.max_radius = std::max({e.radii.x, e.radii.y, e.radii.z});
  return m;
}

inline float ellipsoid_visibility(const glm::vec3& x, const glm::vec3& n, const UnitMap& m,
                                  float alpha_rho) {
  const glm::vec3 u = m.to_unit * (x - m.center);
  const glm::vec3 nu = glm::normalize(m.normal_map * n);
  const Cap k = cap_geometry(u, nu, glm::vec3(0.0f), 1.0f);
  const float volume = m.det * cap_volume(k.h, 1.0f);
  return std::exp(-alpha_rho * off_center_factor(k.h * k.h, k.d2) * volume);
}

// Eq. 7-8 is silent about occluders behind the shaded surface; this is the fraction of the
// occluder's (small, disk-like) silhouette above the tangent plane of the shaded point, where u is
// the silhouette centre's height above the plane in silhouette radii (u >= 1: all of it; u <= -1:
// none; u = 0: half). The end points are exact for any convex occluder; in between it is the area
// of a disk cut by a line (the flat-disk approximation eq. 7 already makes).
inline float above_horizon_fraction(float u) {
  u = std::clamp(u, -1.0f, 1.0f);
  return 1.0f - (std::acos(u) - u * std::sqrt(1.0f - u * u)) / kPi;
}

// Eq. 7-8 for an ellipsoidal large occluder (a sphere is the case of equal radii): the solid angle
// is approximated by the silhouette's area over d^2 (eq. 7: pi r^2 / d^2 for a sphere). An
// ellipsoid {c + A u} seen along the unit direction w has silhouette area pi |det A| |A^-1 w|,
// which is pi r^2 for a sphere. V = 1 - A_SA / (2 pi) (eq. 8), clamped to [0, 1]: eq. 7 exceeds 2
// pi when the point is within r / sqrt(2) of the centre, where it no longer means anything.
// `horizon` multiplies A_SA by above_horizon_fraction (an aoeval addition, see there).
inline float large_occluder_visibility(const glm::vec3& x, const glm::vec3& n, const UnitMap& m,
                                       bool horizon) {
  const glm::vec3 q = m.center - x;
  const float d2 = glm::dot(q, q);
  if (!(d2 > 0.0f)) return 0.0f;
  const float d = std::sqrt(d2);
  float solid_angle = kPi * m.det * glm::length(m.to_unit * q) / (d2 * d);  // eq. 7
  if (horizon)
    solid_angle *= above_horizon_fraction(glm::dot(q, n) / glm::length(m.normal_map * n));
  return std::clamp(1.0f - solid_angle / (2.0f * kPi), 0.0f, 1.0f);  // eq. 8
}

// Eq. 9: V = P_z / (2h) (1 + cos theta) for a point at height P_z on a blade of height h whose
// normal makes the angle theta with the vertical. 1 at the tip facing up, 0 at the root.
inline float grass_visibility(float pz, float h, float cos_theta) {
  const float z = std::clamp(pz, 0.0f, h);
  return std::clamp(z / (2.0f * h) * (1.0f + cos_theta), 0.0f, 1.0f);
}

// Reeves and Blau 1985 as Hegeman et al. §2 describe it: "ambient light on tree leaves is
// attenuated ... based on the depth of the point being shaded inside the tree". The depth is the
// distance from x to the envelope along the ray from the envelope's centre through x: in the unit
// sphere u = A^-1 (x - c) that point is u / |u|, so the depth is (1 - |u|) |x - c| / |u|. For a
// sphere it is exactly the distance to the nearest surface point, R - |x - c|; for an ellipsoid it
// is a closed form that bounds the nearest distance from above and shares its zero set (the
// envelope). At the centre (|u| = 0) the ray is undefined: the smallest semi-axis then. Outside: 0.
inline float envelope_depth(const glm::vec3& x, const UnitMap& m) {
  const glm::vec3 q = x - m.center;
  const float s = glm::length(m.to_unit * q);
  if (s >= 1.0f) return 0.0f;
  if (s < 1e-12f) return m.min_radius;
  return (1.0f - s) * glm::length(q) / s;
}

}  // namespace aoeval::hegeman
