#!/usr/bin/env python3
"""Writes animated.gltf (the glTF test scene of scenes/gltf_scene_test.cpp) and
animated_expected.json: every node's world matrix at every 30 fps frame of each animation,
computed here, independently of aoeval's C++ (own TRS, slerp and cubic Hermite, Python floats).

The scene: a floor, one cube mesh used by two nodes (boxA; boxB under a rotating "rig"), a
perspective camera "cam". Animation "fly": the camera moves (LINEAR translation, CUBICSPLINE
rotation with non-zero tangents) and the rig turns 90 degrees (LINEAR rotation: slerp) while boxB
slides (LINEAR). Animation "hop": boxA jumps (STEP translation).

Usage: python3 make_animated.py [OUT_DIR]   (stdlib only; output is deterministic)
       python3 make_animated.py --bad harness/testdata/bad_input   (the bad-input cases)
"""
import base64
import json
import math
import os
import struct
import sys

FPS = 30.0


def quat_y(deg):
    h = math.radians(deg) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def quat_x(deg):
    h = math.radians(deg) / 2
    return [math.sin(h), 0.0, 0.0, math.cos(h)]


def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz]


def normalize(q):
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


CUBE_P = []
CUBE_N = []
CUBE_I = []
for axis in range(3):
    for sign in (1.0, -1.0):
        n = [0.0, 0.0, 0.0]
        n[axis] = sign
        u = [0.0, 0.0, 0.0]
        v = [0.0, 0.0, 0.0]
        u[(axis + 1) % 3] = 1.0
        v[(axis + 2) % 3] = 1.0
        if sign < 0:
            u, v = v, u
        base = len(CUBE_P)
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            CUBE_P.append([0.5 * (n[k] + a * u[k] + b * v[k]) for k in range(3)])
            CUBE_N.append(n)
        CUBE_I += [base, base + 1, base + 2, base, base + 2, base + 3]

FLOOR_P = [[-5.0, 0.0, -5.0], [5.0, 0.0, -5.0], [5.0, 0.0, 5.0], [-5.0, 0.0, 5.0]]
FLOOR_I = [0, 2, 1, 0, 3, 2]  # counter-clockwise seen from +Y

# Animation keys (times in seconds).
CAM_T = ([0.0, 1.0, 2.0], [[0.0, 1.5, 6.0], [1.0, 1.6, 5.5], [1.5, 2.0, 4.5]])
CAM_R_VALUES = [qmul(quat_y(0.0), quat_x(-8.0)), qmul(quat_y(10.0), quat_x(-10.0)),
                qmul(quat_y(18.0), quat_x(-14.0))]
CAM_R_TANGENTS = [[0.0, 0.02, 0.01, 0.0], [0.01, 0.05, -0.02, 0.0], [0.0, -0.03, 0.0, 0.0]]
RIG_R = ([0.0, 2.0], [quat_y(0.0), quat_y(90.0)])
BOXB_T = ([0.0, 2.0], [[1.2, 0.5, 0.0], [0.8, 0.5, 0.4]])
BOXA_T = ([0.0, 0.5, 1.0], [[-1.2, 0.5, 0.0], [-1.2, 1.0, 0.0], [-1.2, 0.5, 0.0]])

NODES = [
    {"name": "floor", "mesh": 1},
    {"name": "boxA", "mesh": 0, "translation": BOXA_T[1][0]},
    {"name": "rig", "children": [3], "translation": [0.2, 0.0, 0.0]},
    {"name": "boxB", "mesh": 0, "translation": BOXB_T[1][0], "scale": [0.8, 1.2, 0.8]},
    {"name": "cam", "camera": 0, "translation": CAM_T[1][0], "rotation": CAM_R_VALUES[0]},
]
PARENT = {3: 2}


class Buffer:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def add(self, fmt, values, type_, component, target=None, minmax=False):
        while len(self.data) % 4:
            self.data += b"\0"
        offset = len(self.data)
        flat = [x for v in values for x in (v if isinstance(v, list) else [v])]
        self.data += struct.pack("<%d%s" % (len(flat), fmt), *flat)
        view = {"buffer": 0, "byteOffset": offset, "byteLength": len(self.data) - offset}
        if target:
            view["target"] = target
        self.views.append(view)
        acc = {"bufferView": len(self.views) - 1, "componentType": component,
               "count": len(values), "type": type_}
        if minmax:
            n = len(values[0])
            acc["min"] = [min(v[k] for v in values) for k in range(n)]
            acc["max"] = [max(v[k] for v in values) for k in range(n)]
        self.accessors.append(acc)
        return len(self.accessors) - 1


def build():
    b = Buffer()
    cube_p = b.add("f", CUBE_P, "VEC3", 5126, 34962, True)
    cube_n = b.add("f", CUBE_N, "VEC3", 5126, 34962)
    cube_i = b.add("H", CUBE_I, "SCALAR", 5123, 34963)
    floor_p = b.add("f", FLOOR_P, "VEC3", 5126, 34962, True)
    floor_i = b.add("H", FLOOR_I, "SCALAR", 5123, 34963)
    f = lambda xs: b.add("f", xs, "SCALAR", 5126)
    v3 = lambda xs: b.add("f", xs, "VEC3", 5126)
    v4 = lambda xs: b.add("f", xs, "VEC4", 5126)
    cubic = []
    for tan_in, value, tan_out in zip(CAM_R_TANGENTS, CAM_R_VALUES, CAM_R_TANGENTS):
        cubic += [[-c for c in tan_in], value, tan_out]
    fly = {"name": "fly", "samplers": [
        {"input": f(CAM_T[0]), "output": v3(CAM_T[1])},
        {"input": f(CAM_T[0]), "output": v4(cubic), "interpolation": "CUBICSPLINE"},
        {"input": f(RIG_R[0]), "output": v4(RIG_R[1])},
        {"input": f(BOXB_T[0]), "output": v3(BOXB_T[1]), "interpolation": "LINEAR"}],
        "channels": [
        {"sampler": 0, "target": {"node": 4, "path": "translation"}},
        {"sampler": 1, "target": {"node": 4, "path": "rotation"}},
        {"sampler": 2, "target": {"node": 2, "path": "rotation"}},
        {"sampler": 3, "target": {"node": 3, "path": "translation"}}]}
    hop = {"name": "hop", "samplers": [
        {"input": f(BOXA_T[0]), "output": v3(BOXA_T[1]), "interpolation": "STEP"}],
        "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]}
    doc = {
        "asset": {"version": "2.0", "generator": "aoeval scenes/testdata/gltf/make_animated.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 4]}],
        "nodes": NODES,
        "meshes": [
            {"name": "cube", "primitives": [{"attributes": {"POSITION": cube_p, "NORMAL": cube_n},
                                             "indices": cube_i}]},
            {"name": "floorMesh", "primitives": [{"attributes": {"POSITION": floor_p},
                                                  "indices": floor_i}]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 100.0}}],
        "animations": [fly, hop],
        "buffers": [{"byteLength": len(b.data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(bytes(b.data)).decode()}],
        "bufferViews": b.views, "accessors": b.accessors,
    }
    return doc, [fly, hop]


# ---- the independent evaluation: Python floats from the key lists above ----

def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def f32v(v):
    return [f32(x) for x in v]


def slerp(a, b, u):
    d = sum(x * y for x, y in zip(a, b))
    if d < 0:
        b = [-x for x in b]
        d = -d
    if d > 1 - 1e-12:
        return normalize([x + u * (y - x) for x, y in zip(a, b)])
    ang = math.acos(d)
    s = math.sin(ang)
    return [math.sin((1 - u) * ang) / s * x + math.sin(u * ang) / s * y for x, y in zip(a, b)]


def sample(times, values, t, mode, tangents=None):
    """values/tangents as stored in the file (float32); tangents: (in, out) per key."""
    if t <= times[0]:
        return values[0]
    if t >= times[-1]:
        return values[-1]
    k = max(i for i in range(len(times)) if times[i] <= t)
    if mode == "STEP":
        return values[k]
    td = times[k + 1] - times[k]
    u = (t - times[k]) / td
    if mode == "CUBICSPLINE":
        bo = tangents[k][1]
        ai = tangents[k + 1][0]
        h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
        h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
        r = [h00 * p0 + td * h10 * m0 + h01 * p1 + td * h11 * m1
             for p0, m0, p1, m1 in zip(values[k], bo, values[k + 1], ai)]
        return normalize(r) if len(r) == 4 else r
    if len(values[0]) == 4:
        return slerp(values[k], values[k + 1], u)
    return [x + u * (y - x) for x, y in zip(values[k], values[k + 1])]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def trs(t, r, s):
    x, y, z, w = normalize(r)
    rot = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
           [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
           [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m = [[rot[i][j] * s[j] for j in range(3)] + [t[i]] for i in range(3)]
    return m + [[0.0, 0.0, 0.0, 1.0]]


def world(anim_name, t):
    local = []
    for i, n in enumerate(NODES):
        tr = f32v(n.get("translation", [0.0, 0.0, 0.0]))
        ro = f32v(n.get("rotation", [0.0, 0.0, 0.0, 1.0]))
        sc = f32v(n.get("scale", [1.0, 1.0, 1.0]))
        if anim_name == "fly":
            if i == 4:
                tr = sample(f32v(CAM_T[0]), [f32v(v) for v in CAM_T[1]], t, "LINEAR")
                tans = [([-f32(c) for c in tg], f32v(tg)) for tg in CAM_R_TANGENTS]
                ro = sample(f32v(CAM_T[0]), [f32v(v) for v in CAM_R_VALUES], t, "CUBICSPLINE",
                            tans)
            if i == 2:
                ro = sample(f32v(RIG_R[0]), [f32v(v) for v in RIG_R[1]], t, "LINEAR")
            if i == 3:
                tr = sample(f32v(BOXB_T[0]), [f32v(v) for v in BOXB_T[1]], t, "LINEAR")
        if anim_name == "hop" and i == 1:
            tr = sample(f32v(BOXA_T[0]), [f32v(v) for v in BOXA_T[1]], t, "STEP")
        local.append(trs(tr, ro, sc))
    out = []
    for i in range(len(NODES)):
        m = local[i]
        if i in PARENT:
            m = matmul(local[PARENT[i]], m)
        out.append(m)
    return out


def expected():
    result = {"fps": FPS, "yfov": 0.8, "nodes": [n["name"] for n in NODES], "animations": {}}
    for name, end in (("fly", 2.0), ("hop", 1.0)):
        frames = int(math.floor(end * FPS + 1e-6)) + 1
        result["animations"][name] = [
            {"t": k / FPS, "world": world(name, k / FPS)} for k in range(frames)]
    result["rest"] = world(None, 0.0)
    return result


def bad_variants(doc):
    """The bad inputs of issue 44 (harness/testdata/bad_input/gltf_*.gltf), each a one-field edit."""
    import copy
    out = {}
    d = copy.deepcopy(doc)
    d["buffers"][0]["uri"] = "missing.bin"
    out["gltf_missing_buffer"] = d
    d = copy.deepcopy(doc)
    d["meshes"][0]["primitives"][0]["mode"] = 1
    out["gltf_lines"] = d
    d = copy.deepcopy(doc)
    d["accessors"][d["animations"][1]["samplers"][0]["input"]]["count"] = 0
    out["gltf_no_keys"] = d
    d = copy.deepcopy(doc)
    d["nodes"][0]["matrix"] = [1, 0, 0, 0, 0, None, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]  # JS writes NaN as null
    out["gltf_nan_matrix"] = d
    d = copy.deepcopy(doc)
    d["nodes"][4]["translation"] = [-1.2, 0.5, 0.1]  # inside boxA
    out["gltf_camera_inside"] = d
    return out


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--bad":
        for name, d in bad_variants(build()[0]).items():
            with open(os.path.join(sys.argv[2], name + ".gltf"), "w") as fh:
                json.dump(d, fh, separators=(",", ":"))
                fh.write("\n")
        return
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    doc, _ = build()
    with open(os.path.join(out, "animated.gltf"), "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")
    with open(os.path.join(out, "animated_expected.json"), "w") as fh:
        json.dump(expected(), fh)
        fh.write("\n")


if __name__ == "__main__":
    main()
