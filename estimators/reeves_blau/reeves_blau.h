// Reeves and Blau 1985, "Approximate and probabilistic algorithms for shading and rendering
// structured particle systems" (SIGGRAPH '85), as Hegeman, Premoze, Ashikhmin, Drettakis 2006
// ("Approximate Ambient Occlusion for Trees", §2 and Fig. 4, 12) describe and compare against it:
// "ambient light on tree leaves is attenuated by an approximation of leaf self shadowing, which is
// based on the depth of the point being shaded inside the tree ... points deep in the tree are
// darker by an exponential factor of the depth":
//     V = exp(-k depth)
// for pixels of role tree; every other pixel gets 1 (their method has no ground or grass term).
//
// Depth (hegeman_model.h, envelope_depth): the distance from the shaded point to the tree's
// envelope along the ray from the envelope's centre through the point. It is light-independent
// (ambient light has no direction), needs no normal (the original shades particles, which have
// none), is exactly the distance to the nearest surface point for a sphere, is a closed form for an
// ellipsoid (the exact nearest distance needs an iterative root search) and is 0 on and outside the
// envelope, so a point on the envelope gets V = 1.
//
// k: the paper's constants are "ad hoc and do not correspond to parameters in our model" (Fig. 4).
// attenuation = 0 derives k = lambda, the mean number of leaves a ray meets per unit length inside
// the envelope (§3's Poisson argument, tree_proxy.h): the transmittance of the straight path from
// the point to the envelope. At the centre of a sphere that equals the tree-sphere estimator's
// value exp(-lambda R), so the two differ only in how they vary across the crown.
//
// Envelope: a sphere (the leaves' bounding sphere) or an ellipsoid (the moment ellipsoid), from the
// scene's proxy when it has one of that kind (tree_proxy.h). AO definition: uniform, unbounded (the
// comparison of Hegeman et al. eq. 3).
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo reeves_blau_estimator();

}  // namespace aoeval
