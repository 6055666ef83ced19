// Hegeman, Premoze, Ashikhmin, Drettakis 2006, "Approximate Ambient Occlusion for Trees" (I3D '06):
// ambient visibility of trees, the ground near them and grass from a purely local closed form per
// pixel. Three estimators, differing only in the tree's envelope:
//   tree-sphere     eq. 4-6: the plane through the shaded point x with its normal n cuts the
//                   envelope sphere; V = exp(-alpha rho f V_cap) with V_cap the cap's volume (eq.
//                   4) and f = h^2 / (h^2 + d^2) its off-centre factor (eq. 5);
//   tree-ellipsoid  §3 (Fig. 3 right, Fig. 8): the same after mapping the ellipsoid to the unit
//                   sphere (point by A^-1, plane normal by A^T); equal radii give tree-sphere;
//   tree-shells     §5 (Fig. 3 left): several spherical shells from k-means on the leaves; a point
//                   uses the shell with the closest centre.
// Every estimator also shades, per pixel role (scene.objects[objectId].role):
//   tree    its own tree's envelope (above), times eq. 7-8 for every other tree;
//   ground, solid
//           eq. 7-8, "interaction with objects": V = 1 - A_SA / 2pi with A_SA = pi (r/d)^2 the
//           solid angle of each tree's envelope (a sphere; an ellipsoid's silhouette area / d^2;
//           the bounding sphere for shells, since overlapping shells cannot be added), multiplied
//           over trees (independent occluders); a ground pixel inside a grass field's footprint and
//           below its blade tips is a grass pixel at its height instead (parameter grass_ground);
//   grass   eq. 9, V = P_z / (2h) (1 + cos theta), P_z = height above the field's lowest vertex,
//           h = the field's world-space height (for the grass generator exactly facts.blade_height,
//           which is stored in the generator's own space and so is not used directly) or the
//           parameter blade_height, theta = angle between the shading normal and +Y; times eq. 7-8
//           for the trees.
// A scene without trees is fine (no tree pixels); a scene without trees or grass gives AO = 1.
//
// AO definition: uniform weighting, unbounded. The paper's visibility is eq. 3's ambient visibility
// (1/2pi) Int V dw and its derivation (§3, a Poisson count of occluders in the cap) weighs all
// directions alike; nothing in it limits the distance.
//
// alpha rho (eq. 6). The paper picks it by hand per object (§4). alpha_rho = 0 derives it from §3's
// Poisson argument: leaves of one-sided area A_leaf in an envelope of volume V, randomly oriented,
// are met by a ray at the mean rate lambda = G A_leaf / V per unit length (G = 1/2, the mean |cos|
// of a random orientation; with the scene's density rho, lambda = G rho A_leaf / N_leaf), so a ray
// that travels s inside the crown escapes with probability exp(-lambda s). Eq. 6 writes the
// exponent as alpha rho f V_cap: the count of occluders in the cap, rho V_cap, times the chance
// alpha that one of them blocks a given direction. At the sphere's centre (h = R, d = 0, f = 1,
// V_cap = 2/3 pi R^3) every direction travels exactly s = R inside, so the true uniform visibility
// of the Poisson model is exp(-lambda R) with no averaging error; equating gives
//     alpha rho = 3 lambda / (2 pi R^2),  i.e.  alpha = 3 G a / (2 pi R^2):
// three times the fraction of the hemisphere one leaf of area a covers at distance R. For an
// ellipsoid R is the volume-equivalent radius (r1 r2 r3)^(1/3), which makes the exponent at the
// centre lambda (r1 r2 r3)^(1/3); each shell has its own lambda (G times the leaf area inside it
// over its volume) and R. The test PoissonArgumentHoldsAtTheCentreOfSphereUniform checks
// exp(-lambda R) against the Embree reference at the centre of sphere-uniform realisations.
// Elsewhere the model is a heuristic, as the paper says: the cap volume grows like h^2 (3R - h)
// while the mean chord grows about linearly (e.g. on the boundary facing in, the Poisson model
// gives (1 - e^(-2 lambda R)) / (2 lambda R), eq. 6 gives e^(-2 lambda R)). alpha_scale multiplies
// the result (the paper's user-tuned alpha).
//
// Proxies: the scene's (SceneObject::proxy) when it has one of the estimator's kind (a sphere
// serves tree-ellipsoid too), else derived (tree_proxy.h: bounding sphere, moment ellipsoid,
// k-means shells). derive_proxy(), tree_envelopes() and envelope_to_json() (tree_proxy.h) give
// exactly what an estimator uses, lambda included, for the harness to record beside its results.
//
// Pixels are shaded with the shading normal N of the G-buffer (the paper's n); uncovered pixels get
// 1. Per-pixel cost: a few dozen flops and one exp (no allocation; rows in parallel with TBB).
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo tree_sphere_estimator();
EstimatorInfo tree_ellipsoid_estimator();
EstimatorInfo tree_shells_estimator();

}  // namespace aoeval
