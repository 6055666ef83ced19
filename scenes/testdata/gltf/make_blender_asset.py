# Writes blender_animated.glb and blender_expected.json with Blender itself (issue 44, must-show 1):
#
#   cd scenes/testdata/gltf && blender --background --factory-startup \
#       --python make_blender_asset.py
#
# The scene: a floor, one cube mesh used by two objects (boxB is a linked duplicate of boxA: the
# same mesh data), a camera. One action moves the camera (location and rotation keys, Blender's
# default Bezier curves) and one turns and lifts boxB; both play at once, frames 0..60 at 30 fps.
# Blender's glTF exporter (Y up) writes them as one animation, "Animation", sampled at every frame.
#
# blender_expected.json holds, for every frame, what Blender itself evaluates (frame_set, then
# matrix_world), not what the .glb says: each node's world matrix and the camera's, turned into
# glTF's axes as the exporter does: a point p of Blender's world (Z up) is C p in glTF's (Y up) with
# C = [[1,0,0],[0,0,1],[0,-1,0]], so a mesh node's world matrix is C M C^-1 (its vertices are
# converted by C too) and the camera's is C M (Blender's and glTF's cameras both look down their
# -Z with +Y up, so its local axes are kept). "yfov" is the camera's vertical angle (sensor fit
# vertical). The format is animated_expected.json's (make_animated.py): the same C++ test reads
# both (scenes/gltf_scene_test.cpp).
import json
import math

import bpy
from mathutils import Matrix

FPS, LAST = 30, 60
C = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))


def cube_mesh():
    me = bpy.data.meshes.new("cube")
    v = [(x, y, z) for x in (-0.4, 0.4) for y in (-0.4, 0.4) for z in (0.0, 0.8)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    me.from_pydata(v, [], faces)
    me.update()
    return me


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start, scene.frame_end = 0, LAST
    scene.render.resolution_x, scene.render.resolution_y = 320, 240

    floor_me = bpy.data.meshes.new("floor")
    floor_me.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", floor_me)
    box_a = bpy.data.objects.new("boxA", cube_mesh())
    box_a.location = (-1.2, 0.3, 0.0)
    box_b = box_a.copy()  # a linked duplicate: a new object on the same mesh data
    box_b.name = "boxB"
    box_b.location = (1.2, -0.4, 0.0)
    box_b.scale = (0.8, 0.8, 1.2)
    cam_data = bpy.data.cameras.new("cam")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = 0.8
    cam = bpy.data.objects.new("cam", cam_data)
    for o in (floor, box_a, box_b, cam):
        scene.collection.objects.link(o)
    scene.camera = cam

    # The camera: flies in and turns (Euler keys in Blender; the exporter writes quaternions).
    for f, loc, rot in ((0, (0.0, -6.0, 1.5), (80, 0, 0)), (30, (1.5, -4.5, 1.8), (76, 0, 12)),
                        (60, (2.5, -3.0, 2.2), (70, 0, 30))):
        cam.location = loc
        cam.rotation_euler = [math.radians(a) for a in rot]
        cam.keyframe_insert("location", frame=f)
        cam.keyframe_insert("rotation_euler", frame=f)
    # boxB: turns about its vertical axis and lifts.
    for f, z, yaw in ((0, 0.0, 0), (40, 0.3, 60), (60, 0.1, 100)):
        box_b.location.z = z
        box_b.rotation_euler = (0, 0, math.radians(yaw))
        box_b.keyframe_insert("location", frame=f)
        box_b.keyframe_insert("rotation_euler", frame=f)

    nodes = ["floor", "boxA", "boxB", "cam"]
    frames = []
    for f in range(0, LAST + 1):
        scene.frame_set(f)
        world = []
        for name in nodes:
            m = bpy.data.objects[name].matrix_world
            m = C @ m if name == "cam" else C @ m @ C.inverted()
            world.append([list(row) for row in m])
        frames.append({"t": f / FPS, "world": world})

    bpy.ops.export_scene.gltf(filepath="blender_animated.glb", export_format="GLB",
                              export_yup=True, export_cameras=True, export_animations=True,
                              export_force_sampling=True, export_nla_strips=False,
                              export_frame_range=True, export_apply=False)
    expected = {"fps": FPS, "yfov": cam_data.angle_y, "nodes": nodes,
                "generator": "make_blender_asset.py, Blender " + bpy.app.version_string,
                "animations": {"Animation": frames}}
    with open("blender_expected.json", "w") as out:
        json.dump(expected, out)


main()
