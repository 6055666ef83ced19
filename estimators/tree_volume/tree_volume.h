// tree-volume: the per-direction Beer-Lambert version of Hegeman, Premoze, Ashikhmin, Drettakis
// 2006, "Approximate Ambient Occlusion for Trees" (I3D '06). Beyond the paper: it keeps §3's
// Poisson argument (the chance that no occluder lies between x and the outside of the crown) but
// applies it per direction instead of to the whole cap at once (eq. 6):
//     V(x, n) = Int_{H(n)} exp(-lambda chord(x, w)) W(w) dw
// with chord(x, w) the length of the ray x + t w inside the tree's proxy and W uniform (eq. 3) or
// cosine (parameter `weighting`). Why: eq. 6's exponent grows like the cap *volume*, so a point
// near the crown's surface facing out comes out too bright and one facing in far too dark, while
// the Poisson count along a ray grows with the *path length* (volume_model.h).
//
// lambda is derived from the leaves exactly as tree-sphere derives alpha rho (tree_proxy.h: lambda
// = G A_leaf / V, G = 1/2, i.e. N a / 2 for N randomly oriented two-sided leaves of area a per unit
// volume; with the scene's density rho, G rho A_leaf / N_leaf), times `lambda_scale`.
//
// Proxies (parameter `proxy`), the scene's when it has one of the kind, else derived:
//   sphere     the chord through the bounding sphere (closed form per direction);
//   ellipsoid  the chord through the ellipsoid, found in its unit-sphere space (an affine map keeps
//              the ray parameter, so the root's t is a world length);
//   shells     §5's k-means shells, each point of space belonging to the shell with the closest
//              centre (§5's rule, applied along the ray): the ray's interval in shell k is clipped
//              to the half-spaces closer to c_k than to every other centre, and the optical depth
//              is sum_k lambda_k length_k. The cells partition space, so overlapping shells are
//              never counted twice; lambda_k is shell k's local density (tree_proxy.h).
// At the centre of a sphere the integral is exp(-lambda R) in closed form for every n; elsewhere a
// fixed product rule of rings x azimuths directions (volume_model.h), the same for every pixel, so
// the image is deterministic and smooth (no noise, only quadrature error).
//
// Ground, grass and the other trees are shaded exactly as tree-sphere shades them (tree_scene.h:
// eq. 7-8, eq. 9), whatever the weighting.
//
// Cost per tree pixel: rings x azimuths chords (a few dot products and a sqrt each) and as many
// exps: about 32 x tree-sphere's single exp at the default 4 x 8 (`aoeval bench estimators`).
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo tree_volume_estimator();

}  // namespace aoeval
