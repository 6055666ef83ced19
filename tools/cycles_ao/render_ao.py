# Renders Cycles' ambient-occlusion pass of a scene that `aoeval scenes export` wrote, headless:
#
#   blender --background --factory-startup --python tools/cycles_ao/render_ao.py -- \
#       --ply scene.ply --camera camera.json --spp 256 --seed 1 --distance 1e30 --out cycles.exr
#
# Run by tools/cycles_ao/compare.py; it writes one multilayer OpenEXR (32-bit float) holding the
# passes AO (R = G = B), Position (world, first hit), Combined (its alpha is the coverage).
#
# What Cycles' AO pass is (Blender 3.4, intern/cycles/kernel/integrator/shade_surface.h,
# integrate_surface_ao, and shade_shadow.h): at a camera ray's first hit, one direction per sample
# drawn cosine-weighted around the shading normal (sample_cos_hemisphere), one shadow ray from the
# point offset off the surface, up to the world's AO distance (World > Ambient Occlusion >
# Distance, world.light_settings.distance); an unoccluded ray adds the path throughput (1 for a
# camera ray on an opaque surface), an occluded one adds 0. So the pass is the fraction of
# cosine-weighted rays unoccluded within the distance, not multiplied by albedo: aoeval's cosine
# AO with dmax = that distance and falloff none (CONTRACT section 3). compare.py checks this on an
# open plane (1) and inside a closed box (0) before it trusts it on a level.
#
# Matching aoeval's conventions (CONTRACT section 3):
# - Geometry: the PLY's world coordinates as they are (aoeval's +Y-up world is placed in Blender's
#   world unchanged; AO has no preferred direction, so nothing is turned), every face flat shaded:
#   the geometric normal, aoeval's `--normal geometric`.
# - Camera: its world matrix has columns right, up, -forward, eye (a Blender camera looks down its
#   -Z with +Y up), vertical sensor fit with the view's vertical field of view.
# - Pixels: Cycles samples pixel (i, j) at raster (i + 0.5, j + 0.5) plus the pixel filter's
#   offset; a Gaussian filter 0.01 px wide (the least Cycles allows) keeps every sample within
#   0.005 px of the centre. Not the box filter: Blender's sync makes a box 1 px wide whatever
#   filter_width says, and its samples then spread over the whole pixel (a silhouette pixel mixed
#   the AO of two surfaces: on oa-dm4/hall at dmax 1 the mean differed by 8.5 standard errors).
#   Blender writes the EXR with its top row first, as aoeval does. compare.py checks the camera,
#   the pixel centre and y with the Position pass (Cycles writes it from sample 0 only) against
#   aoeval's G-buffer P, and the filter's width with the alpha of silhouette pixels (fractional
#   alpha = samples off the centre).
# - Two-sided: Cycles flips N and Ng of a back-facing hit towards the ray, as aoeval does.
import argparse
import json
import sys

import bpy
import numpy as np
from mathutils import Matrix


def read_ply(path):
    """The binary little-endian PLY that write_scene_ply (scenes/scene_export.h) writes."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    counts = {}
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if words[:1] == ["element"]:
            counts[words[1]] = int(words[2])
    nv, nf = counts["vertex"], counts["face"]
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end)
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<u4", 3)]), count=nf,
                          offset=end + 12 * nv)
    if nf and not np.all(faces["n"] == 3):
        sys.exit(f"{path}: a face is not a triangle")
    return vertices, faces["i"].ravel()


def build_mesh(vertices, indices):
    mesh = bpy.data.meshes.new("scene")
    nv, nf = len(vertices) // 3, len(indices) // 3
    mesh.vertices.add(nv)
    mesh.vertices.foreach_set("co", vertices)
    mesh.loops.add(3 * nf)
    mesh.loops.foreach_set("vertex_index", indices.astype(np.int32))
    mesh.polygons.add(nf)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * nf, 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(nf, 3, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.zeros(nf, dtype=bool))
    mesh.update(calc_edges=True)  # no validate(): it would drop degenerate triangles
    return mesh


def build_camera(c):
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = np.radians(c["fov_y_deg"])
    cam.clip_start = 1e-4
    cam.clip_end = 1e30
    obj = bpy.data.objects.new("camera", cam)
    right, up, forward, eye = (c[k] for k in ("right", "up", "forward", "eye"))
    obj.matrix_world = Matrix((
        (right[0], up[0], -forward[0], eye[0]),
        (right[1], up[1], -forward[1], eye[1]),
        (right[2], up[2], -forward[2], eye[2]),
        (0.0, 0.0, 0.0, 1.0),
    ))
    return obj


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--ply", required=True)
    p.add_argument("--camera", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--distance", type=float, default=1e30, help="AO distance (aoeval's dmax)")
    p.add_argument("--threads", type=int, default=0, help="0: as many as cores")
    p.add_argument("--pixel-filter", default="GAUSSIAN", choices=["GAUSSIAN", "BOX"],
                   help="BOX only to show the check failing (it is 1 px wide)")
    a = p.parse_args(argv)
    with open(a.camera) as f:
        c = json.load(f)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    vertices, indices = read_ply(a.ply)
    scene.collection.objects.link(bpy.data.objects.new("scene", build_mesh(vertices, indices)))
    camera = build_camera(c)
    scene.collection.objects.link(camera)
    scene.camera = camera

    world = bpy.data.worlds.new("world")
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    world.light_settings.distance = a.distance
    scene.world = world

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = c["width"], c["height"]
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = True  # Combined alpha = coverage
    r.use_persistent_data = False
    if a.threads > 0:
        r.threads_mode, r.threads = "FIXED", a.threads
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = a.spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = a.seed
    cy.use_animated_seed = False
    cy.pixel_filter_type = a.pixel_filter  # a box is 1 px wide whatever its width (see above)
    cy.filter_width = 0.01
    cy.max_bounces = 0  # only the first hit matters: the AO pass is made there
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    layer = scene.view_layers[0]
    layer.use_pass_ambient_occlusion = True
    layer.use_pass_position = True
    scene.view_settings.view_transform = "Standard"
    settings = r.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    r.filepath = a.out
    r.use_file_extension = False
    bpy.ops.render.render(write_still=True)


main()
