// The per-direction Poisson (Beer-Lambert) visibility behind tree-volume, inline and
// allocation-free: the estimator calls it once per pixel, the tests call it directly.
//
// Hegeman et al. 2006 §3 argue that, for occluders scattered at random in the crown, the chance
// that a direction from x escapes is the chance of finding zero occluders in a Poisson process.
// Along one direction w that process counts the leaves the ray x + t w meets: with lambda leaves
// met per unit length (lambda = G A_leaf / V, G = 1/2 for randomly oriented flat leaves:
// tree_proxy.h), the count is Poisson with mean lambda * chord(x, w), the length of the ray inside
// the crown, so
//     P(escape | w) = exp(-lambda chord(x, w))
// and ambient visibility is its hemisphere average (eq. 3 with V_x(w) replaced by its expectation):
//     V(x, n) = Int_{H(n)} exp(-lambda chord(x, w)) W(w) dw,  W = 1/(2 pi) (uniform) or
//     cos(theta)/pi (cosine).
// Eq. 6 instead puts the whole cap volume in one exponent; this keeps §3's argument per direction.
//
// Closed form: at the centre of a sphere every chord is R, so V = exp(-lambda R) for any n and
// either weighting. Off centre the hemisphere cut by an arbitrary plane has no elementary
// integral, so V is a fixed product rule: Gauss-Legendre in mu = cos(theta) (`rings` nodes, exact
// for polynomials of degree 2 rings - 1 in mu) times the trapezoid rule in the azimuth (`azimuths`
// nodes, spectrally accurate for a periodic integrand), alternate rings offset by half a step.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <vector>

namespace aoeval::volume {

// Gauss-Legendre nodes and weights on [0, 1] (weights sum to 1), by Newton's method on the
// Legendre polynomial in double (deterministic; converges to rounding in a few steps).
struct GaussLegendre {
  std::vector<double> nodes, weights;
};
inline GaussLegendre gauss_legendre(int m) {
  GaussLegendre g;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < m; ++i) {
    double x = std::cos(pi * (i + 0.75) / (m + 0.5)), dp = 1.0;  // root i of P_m on [-1, 1]
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= m; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = m * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-16) break;
    }
    g.nodes.push_back(0.5 * (1.0 - x));
    g.weights.push_back(1.0 / ((1.0 - x * x) * dp * dp));  // 2 / ((1 - x^2) P'^2), halved
  }
  return g;
}

// The fixed direction set in the local frame (z = the normal) with weights summing to 1.
struct DirectionSet {
  std::vector<glm::vec3> dirs;
  std::vector<float> weights;
};
inline DirectionSet direction_set(int rings, int azimuths, bool cosine) {
  const GaussLegendre g = gauss_legendre(rings);
  const double two_pi = 6.28318530717958647692;
  DirectionSet s;
  double total = 0.0;
  std::vector<double> w;
  for (int i = 0; i < rings; ++i) {
    const double mu = g.nodes[static_cast<size_t>(i)];
    // d(omega) = d(mu) d(phi): uniform weight 1, cosine weight 2 mu (both integrate to 1 on [0,1]).
    const double ring = g.weights[static_cast<size_t>(i)] * (cosine ? 2.0 * mu : 1.0);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    for (int j = 0; j < azimuths; ++j) {
      const double phi = two_pi * (j + 0.5 * (i % 2)) / azimuths;
      s.dirs.emplace_back(static_cast<float>(sin_t * std::cos(phi)),
                          static_cast<float>(sin_t * std::sin(phi)), static_cast<float>(mu));
      w.push_back(ring / azimuths);
      total += ring / azimuths;
    }
  }
  for (double v : w) s.weights.push_back(static_cast<float>(v / total));
  return s;
}

// An orthonormal frame whose third axis is the unit vector n (Duff et al. 2017, branchless).
inline glm::mat3 frame(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  return glm::mat3(glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x),
                   glm::vec3(b, sign + n.y * n.y * a, -n.y), n);
}

// The parameter interval [t0, t1] (t0 >= 0) of the ray u + t du inside the unit sphere, in the
// ray's own parameter (a world length when du is the image of a unit world direction): the roots
// of |u + t du|^2 = 1. Empty (t1 <= t0) when the ray misses it or it lies behind.
struct Interval {
  float t0 = 0.0f, t1 = 0.0f;
  float length() const { return std::max(0.0f, t1 - t0); }
};
inline Interval unit_sphere_interval(const glm::vec3& u, const glm::vec3& du) {
  const float a = glm::dot(du, du), b = glm::dot(u, du), c = glm::dot(u, u) - 1.0f;
  const float disc = b * b - a * c;
  if (!(disc > 0.0f) || !(a > 0.0f)) return {};
  const float s = std::sqrt(disc);
  return {std::max(0.0f, (-b - s) / a), (-b + s) / a};
}

// The chord of the ray x + t w (|w| = 1, t >= 0) through the sphere (c, R): the closed form
// sqrt(R^2 - |q|^2 + (q.w)^2) - q.w from inside, q = x - c.
inline float sphere_chord(const glm::vec3& x, const glm::vec3& w, const glm::vec3& c, float R) {
  return unit_sphere_interval((x - c) / R, w / R).length();
}

}  // namespace aoeval::volume
