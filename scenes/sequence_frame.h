// One frame of a sequence view (CONTRACT §10): its camera, its posed geometry, and the G-buffer's
// motion.X/Y and disoccluded channels, computed from the known camera and object motion (not
// optical flow), so that every estimator, the reference and the temporal scores see the same
// exact correspondences.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <vector>

#include "scenes/camera.h"
#include "scenes/embree_scene.h"
#include "scenes/gbuffer.h"
#include "scenes/scene.h"

namespace aoeval {

struct SequenceFrame {
  int index = 0;
  View view;               // eye and target of this frame (the sequence kept)
  glm::vec2 jitter{0.0f};  // sub-pixel sample offset (Camera::jitter)
  // Per G-buffer object id (instances.h PlacementIds; = per scene object without instances): the
  // world-space motion from its placement. Every instance of an instanced object named in the
  // sequence's "objects" moves with the whole group (pivot: the centre of all its copies).
  std::vector<glm::mat4> motion;
  bool moves_objects = false;  // some object's motion is not the identity at this frame
};

// Frame `k` of `view` (a view without a sequence has one frame, 0). InputError naming the view and
// the frame range when k is outside it.
SequenceFrame sequence_frame(const Scene& scene, const View& view, int k);
// Whether two frames pose the same geometry and see it through the same camera (eye, target,
// jitter and every object's motion equal): their G-buffers and references are the same.
bool same_pose(const SequenceFrame& a, const SequenceFrame& b);
// The first frame j <= k such that frames j..k all pose what frame k does: frame k's reference is
// frame j's (issue 42: a frame that does not change is traced once, with frame j's seed).
int unchanged_since(const Scene& scene, const View& view, int k);
// The frame's camera at a resolution (the view's own when 0), jitter included.
Camera frame_camera(const SequenceFrame& frame, int width = 0, int height = 0);
// `base` with the frame's object motions applied to meshes and tree proxies; its content_hash()
// is therefore the frame's geometry, which is what keys the frame's cached references.
Scene posed_scene(const Scene& base, const SequenceFrame& frame);

// Continuous pixel coordinates (x right, y down; pixel (i, j)'s centre at (i + 0.5, j + 0.5)) of
// world point `p` in `camera`, without jitter; false when p is not in front of the camera. `depth`
// is its linear view depth. Double precision: motion vectors are checked to 1e-3 px.
bool project_to_pixel(const Camera& camera, const glm::dvec3& p, glm::dvec2& pixel, double& depth);

// Fills cur.motion and cur.disoccluded (CONTRACT §10). For each covered pixel, its surface point
// P_k is taken back into its object's frame k - 1 pose (motion_prev * inverse(motion_cur)) and
// projected with frame k - 1's camera: motion = proj_k(P_k) - proj_{k-1}(P_{k-1}), both without
// jitter (so a static camera with jitter has zero motion, as TAA expects). `prev` == nullptr
// (frame 0): motion 0, nothing disoccluded.
//
// Disocclusion, a reprojected depth/objectId test against frame k - 1's G-buffer: the point is
// disoccluded when proj_{k-1}(P_{k-1}) falls off the image or behind the camera, or the pixel of
// frame k - 1 nearest to it (its jittered sample positions considered) is uncovered, shows another
// object, or shows a surface whose plane (P, Ng of that pixel) lies farther from P_{k-1} than one
// pixel footprint at P_{k-1}'s depth (2 z tan(fov/2) / height). Why that tolerance: the nearest
// pixel's sample is up to 0.71 px from P_{k-1}, so on a curved surface of radius R its tangent
// plane deviates by up to about (0.71 footprint)^2 / (2 R), under a footprint for any R above a
// quarter footprint, while a surface hidden behind another part of the same object sits more
// than a pixel footprint behind it for any occluder the image can resolve. A plane distance (not
// a depth difference) keeps grazing floors, whose depth changes fast across a pixel, visible.
void add_motion(GBuffer& cur, const GBuffer* prev, const std::vector<glm::mat4>& motion_cur,
                const std::vector<glm::mat4>& motion_prev);

// Frame k's G-buffer at a resolution (0 = the view's), with motion and disocclusion (frame k - 1 is
// posed and rendered for them): what `aoeval gbuffer --frame K` writes. A still view's frame 0 is
// its plain G-buffer, without those channels.
GBuffer render_frame_gbuffer(const Scene& base, const View& view, int k, int width = 0,
                             int height = 0);
// The G-buffer's (and reference's) header attributes of frame k: gbuffer_attributes of the posed
// scene and the frame's camera, plus aoeval:frame for sequence views.
Attributes frame_attributes(const Scene& posed, const View& view, const Camera& camera, int k);

}  // namespace aoeval
