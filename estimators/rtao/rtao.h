// rtao: real-time ray-traced AO as engines ship it (the Microsoft D3D12 Raytracing Real-Time
// Denoised Ambient Occlusion sample; UE and HDRP's ray-traced AO): a few cosine rays per pixel per
// frame, then a spatio-temporal denoiser after SVGF (Schied et al. 2017, "Spatiotemporal
// Variance-Guided Filtering: Real-Time Reconstruction for Path-Traced Global Illumination", HPG
// 2017). Per frame:
//
//  1. rays: `rays` cosine-weighted rays per pixel with Embree through the shared tracer
//     (sampling/ao_tracer.h, the reference's own algorithm), bounded by t_max (= dmax) with the
//     chosen falloff. The directions are a low-discrepancy sequence that advances per frame with
//     per-pixel scrambling: each pixel owns an Owen-scrambled Sobol sequence (Burley 2020,
//     "Practical Hash-based Owen Scrambling", its scramble hashed from seed and pixel) and frame k
//     takes its points k rays .. (k + 1) rays - 1, so a pixel's rays over 2^n frames form a
//     (0, n, 2)-net and temporal accumulation integrates a stratified set, not white noise.
//  2. temporal: the shared stage (estimators/temporal/temporal_stage.h): reprojection through the
//     motion vectors, disocclusion reset, exponential history, neighbourhood clamp, and the first
//     two moments (SVGF §4.1).
//  3. variance: from the moments, spatially (7x7 bilateral, variance_radius 3) where the history
//     is short (§4.2).
//  4. a-trous: `atrous_iterations` edge-avoiding wavelet passes with the depth, normal and
//     variance edge-stopping weights sigma_z, sigma_n, sigma_l (§4.3-4.4, eqs. 1-5, svgf.h); the
//     first pass's output is the next frame's history (§4.1).
//
// Over a sequence it keeps state (EstimatorInfo::keeps_state): one instance runs every frame in
// order, and applies the seed rule itself: frame k takes sample indices seed_offset x rays on
// (FrameInfo::seed_offset, k unless the run says "seed_per_frame": false, when every frame
// traces the same rays). On a still view (no FrameInfo) and at frame 0 it runs as frame 0 with no
// history, and the row's derived params say so. Per-pass times in pass_ms: rays_ms, temporal_ms,
// variance_ms (with the one read of the G-buffer's channels the SVGF weights share, svgf.h),
// atrous_ms and atrous_<i>_ms per pass (wall clock of each CPU stage).
#pragma once

#include "estimators/estimator.h"

namespace aoeval {

EstimatorInfo rtao_estimator();

}  // namespace aoeval
