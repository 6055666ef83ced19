// vertex-baked: Matt Pharr and Simon Green, 2004, "Ambient Occlusion", GPU Gems, chapter 17
// (after Landis 2002). Implements §17.2 (Listing 17-1): per triangle, `rays` uniform directions
// over the hemisphere at the triangle's centre (the distribution of Listing 17-2), accessibility =
// numUnoccluded / numRays and the average unoccluded direction (the bent normal); the values are
// averaged to the vertices ("the average of the values from the adjacent faces", here
// area-weighted) and interpolated per pixel (§17.4, the vertex-shader path; Figure 17-3 shades with
// accessibility alone). The shading with a blurred environment map (Listings 17-3 to 17-5) is out
// of scope: aoeval scores the accessibility, and writes the bent normal as extra channels
// bent.X/Y/Z.
//
// AO definition: uniform weighting, unbounded (CONTRACT §3: "GPU Gems ch. 17 accessibility").
// Surfaces are two-sided: both sides of every triangle are baked (twice the rays of a one-sided
// bake), and a pixel reads the side its viewer is on, the side its G-buffer normal faces.
// The preprocess (prepare(), precompute_ms) costs 2 * rays * 4^subdivide * triangles occlusion
// rays; a frame (run()) re-traces one primary ray per pixel to find the triangle and barycentrics
// and interpolates. Bake and lookup: vertex_bake.h.
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo vertex_baked_estimator();

}  // namespace aoeval
