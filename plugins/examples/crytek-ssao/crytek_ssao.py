#!/usr/bin/python3
"""Crytek-style screen-space ambient occlusion (Mittring 2007), an aoeval process plug-in.

The template to copy for your own estimator: read the G-buffer and the parameters, compute AO in
[0, 1] (1 = open) per pixel, write AO.exr, and optionally time your frames. aoeval runs

    python3 crytek_ssao.py --gbuffer G.exr --params P.json --out AO.exr --frames N

in this folder. G.exr holds the channels of CONTRACT §4 (A, Z, P.X.., N.X.., Ng.X.., objectId)
and the camera as JSON in its "aoeval:camera" header attribute. P.json maps every parameter of
estimator.json to its value. Anything written to stderr is quoted when the run fails.

Over time, the same program serves `"protocol": "frames"` (CONTRACT §10; the crytek-ssao-frames
example runs it so): started once as `python3 crytek_ssao.py --protocol frames`, it reads one JSON
request per line on stdin, {"frame": K, "gbuffer": G, "params": P, "out": O}, computes that frame
and answers {"frame": K, "ok": true} (or {"frame": K, "error": "..."}) on stdout, until EOF. Its
imports (numpy, OpenImageIO: most of a run's time at small sizes) are then paid once per sequence,
not once per frame. P.json's seed is the frame's (seed + K, the seed rule), so the sample offsets
change every frame.

Algorithm (Mittring 2007, §8.5.4.3): for each pixel's point P, `samples` points S_i uniform in the
ball of radius R around P (reflected into the normal's hemisphere when `hemisphere`, after Filion
and McNaughton 2008) are projected to the screen; S_i is occluded when the depth buffer there is
in front of S_i by more than `bias` and by less than R (the range check that keeps far
foreground objects from darkening the background). AO = 1 - occluded / samples.
"""
import argparse
import json
import sys
import time

import numpy as np
import OpenImageIO as oiio


def read_gbuffer(path):
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit("cannot open %s: %s" % (path, oiio.geterror()))
    spec = image.spec()
    pixels = image.read_image(0, 0, 0, spec.nchannels, "float")
    image.close()
    channels = {name: pixels[:, :, c] for c, name in enumerate(spec.channelnames)}
    camera = json.loads(spec.getattribute("aoeval:camera"))
    return channels, camera


def crytek_ssao(g, camera, p, rng_offsets):
    height, width = g["Z"].shape
    eye, fwd = np.array(camera["eye"]), np.array(camera["forward"])
    right, up = np.array(camera["right"]), np.array(camera["up"])
    focal = height / (2.0 * np.tan(np.radians(camera["fov_y_deg"]) / 2.0))
    covered = g["A"] > 0.5
    pos = np.stack([g["P.X"], g["P.Y"], g["P.Z"]], axis=-1)[covered]  # (n, 3) world
    nrm = np.stack([g["N.X"], g["N.Y"], g["N.Z"]], axis=-1)[covered]
    depth = np.where(covered, g["Z"], np.inf)  # background never occludes

    occluded = np.zeros(len(pos))
    for offset in rng_offsets:  # (n, 3) unit-ball offsets, one sample per pixel at a time
        if p["hemisphere"]:
            flip = np.sum(offset * nrm, axis=1) < 0.0
            offset = np.where(flip[:, None], -offset, offset)
        s = pos + p["radius"] * offset - eye
        z = s @ fwd  # the sample's own linear depth
        zs = np.maximum(z, 1e-6)
        i = np.floor(0.5 * width + focal * (s @ right) / zs).astype(np.int64)
        j = np.floor(0.5 * height - focal * (s @ up) / zs).astype(np.int64)
        inside = (z > 1e-6) & (i >= 0) & (i < width) & (j >= 0) & (j < height)
        scene_z = np.full(len(pos), np.inf)
        scene_z[inside] = depth[j[inside], i[inside]]
        gap = z - scene_z  # > 0: the visible surface is in front of the sample
        occluded += (gap > p["bias"]) & (gap < p["radius"])

    ao = np.zeros((height, width), dtype=np.float32)
    ao[covered] = 1.0 - occluded / len(rng_offsets)
    return ao


def ball_offsets(seed, samples, n):
    """`samples` arrays of n points uniform in the unit ball (direction x radius^(1/3))."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(samples):
        d = rng.normal(size=(n, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        out.append(d * rng.random((n, 1)) ** (1.0 / 3.0))
    return out


def estimate(gbuffer, params, out, frames=1):
    """One frame: reads the G-buffer and the parameters, writes AO and its timing file."""
    g, camera = read_gbuffer(gbuffer)
    with open(params) as f:
        p = json.load(f)
    n = int(np.count_nonzero(g["A"] > 0.5))
    offsets = ball_offsets(p["seed"], p["samples"], n)

    frame_ms = []
    for _ in range(max(1, frames)):
        t0 = time.perf_counter()
        ao = crytek_ssao(g, camera, p, offsets)
        frame_ms.append(1000.0 * (time.perf_counter() - t0))

    spec = oiio.ImageSpec(ao.shape[1], ao.shape[0], 1, "float")
    spec.channelnames = ("AO",)
    image = oiio.ImageOutput.create(out)
    # (height, width, 1): OpenImageIO 2.4's Python binding misreads a 2-D array.
    if image is None or not image.open(out, spec) or not image.write_image(ao[:, :, None]):
        sys.exit("cannot write %s: %s" % (out, oiio.geterror()))
    image.close()
    # Optional: our own per-frame times, so the row times the algorithm, not Python's start-up.
    with open(out + ".timing.json", "w") as f:
        json.dump({"frame_ms": frame_ms}, f)


def serve_frames():
    """The frames protocol: one request line in, one answer line out (flushed), until EOF."""
    for line in sys.stdin:
        request = json.loads(line)
        answer = {"frame": request["frame"]}
        try:
            estimate(request["gbuffer"], request["params"], request["out"])
            answer["ok"] = True
        except Exception as e:  # the frame fails, with its reason; the program goes on
            print("frame %d: %r" % (request["frame"], e), file=sys.stderr)
            answer["error"] = repr(e)
        print(json.dumps(answer), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--protocol", choices=["run", "frames"], default="run")
    ap.add_argument("--gbuffer")
    ap.add_argument("--params")
    ap.add_argument("--out")
    ap.add_argument("--frames", type=int, default=1)
    args = ap.parse_args()
    if args.protocol == "frames":
        serve_frames()
    elif not (args.gbuffer and args.params and args.out):
        ap.error("--gbuffer, --params and --out are required (or --protocol frames)")
    else:
        estimate(args.gbuffer, args.params, args.out, args.frames)


if __name__ == "__main__":
    main()
