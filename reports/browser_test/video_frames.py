#!/usr/bin/python3
# The browser test's ground truth for the sequence videos (CONTRACT §10: "the video of the
# estimate beside the reference's"): for every sequence point under a report folder with two kept
# frames, the 8-bit greys its first and last kept frames must show, computed from the
# kept EXRs with OpenImageIO (Debian's python3-openimageio, independent of aoeval's C++ drawing):
# grey = round(255 * sRGB(clamp(AO, 0, 1))) at pixels covered in both images (drawing/
# error_maps.cpp grey_panel's rule; other pixels are painted as "not compared" and not checked).
#
#   video_frames.py OUT_DIR OUT.json
import base64, glob, json, os, sys

import numpy as np
import OpenImageIO as oiio


def ao_and_cover(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(f"video_frames.py: {path}: {buf.geterror()}")
    pixels = buf.get_pixels(oiio.FLOAT)
    spec = buf.spec()
    return pixels[:, :, spec.channelindex("AO")], pixels[:, :, spec.channelindex("A")]


def grey(ao):
    v = np.clip(ao.astype(np.float64), 0.0, 1.0)
    s = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)
    return np.rint(s * 255.0).astype(np.uint8)


def b64(a):
    return base64.b64encode(np.ascontiguousarray(a).tobytes()).decode()


def main():
    out_dir, out = sys.argv[1], sys.argv[2]
    videos = []
    for manifest in sorted(glob.glob(os.path.join(out_dir, "**", "sequence.json"), recursive=True)):
        kept = [k for k in json.load(open(manifest)).get("kept", []) if "reference" in k]
        if len(kept) < 2:
            continue
        frames = []
        for index in (0, len(kept) - 1):  # the video holds every kept frame, in order
            ref, ref_a = ao_and_cover(os.path.join(out_dir, kept[index]["reference"]))
            est, est_a = ao_and_cover(os.path.join(out_dir, kept[index]["estimate"]))
            mask = ((ref_a == 1.0) & (est_a == 1.0)).astype(np.uint8)
            frames.append({"index": index, "frame": kept[index]["frame"],
                           "width": int(ref.shape[1]), "height": int(ref.shape[0]),
                           "reference": b64(grey(ref)), "estimate": b64(grey(est)),
                           "mask": b64(mask)})
        # The page's video element names its point's manifest (relative to the report folder).
        videos.append({"manifest": os.path.relpath(manifest, out_dir), "frames": len(kept),
                       "check": frames})
    if not videos:
        sys.exit(f"video_frames.py: {out_dir}: no sequence video with two kept frames")
    json.dump(videos, open(out, "w"))


main()
