#!/usr/bin/python3
"""Writes AO = value everywhere: an aoeval process plug-in that does no work, so that its time is
the protocol's overhead (start-up, reading G.exr's header, writing AO.exr). Each of the --frames N
frames builds the constant image anew and times itself."""
import argparse
import json
import time

import numpy as np
import OpenImageIO as oiio

ap = argparse.ArgumentParser()
ap.add_argument("--gbuffer", required=True)
ap.add_argument("--params", required=True)
ap.add_argument("--out", required=True)
ap.add_argument("--frames", type=int, default=1)
args = ap.parse_args()

spec_in = oiio.ImageInput.open(args.gbuffer)
width, height = spec_in.spec().width, spec_in.spec().height
spec_in.close()
with open(args.params) as f:
    value = float(json.load(f)["value"])

frame_ms = []
for _ in range(max(1, args.frames)):
    t0 = time.perf_counter()
    ao = np.full((height, width, 1), value, dtype=np.float32)  # OIIO 2.4 misreads 2-D arrays
    frame_ms.append(1000.0 * (time.perf_counter() - t0))

spec = oiio.ImageSpec(width, height, 1, "float")
spec.channelnames = ("AO",)
out = oiio.ImageOutput.create(args.out)
out.open(args.out, spec)
out.write_image(ao)
out.close()
with open(args.out + ".timing.json", "w") as f:
    json.dump({"frame_ms": frame_ms}, f)
