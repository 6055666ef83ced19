#!/usr/bin/python3
# The browser test's ground truth for the viewer's probe: reads the EXRs behind a page's viewers
# with OpenImageIO (Debian's python3-openimageio, independent of aoeval's C++ reader) and writes,
# for each viewer, `count` random covered pixels (A = 1 in both images, fixed seed) with the float32
# values of the reference's AO and AO_stderr and the estimate's AO; and, as the pixel the viewer
# test zooms to, the darkest compared pixel of the reference (a crease: where AO errors live).
#
# A still view's viewer whose static image is an error mosaic (drawing/error_maps.h) also gets
# "mosaic": what the mosaic PNG says it shows (its "aoeval:mosaic" text: p99, scale, the colour
# bars' labels), the 8-bit colours of the |error| and signed-error panels at each sample pixel,
# and the colours at both ends of each colour bar, for check_viewer.js to hold the viewer beside.
# A G-buffer gallery page (viewers of kind "gbuffer"): its Z and N.X/Y/Z at covered pixels.
# A sequence point's maps (kind "maps"): flicker and lag at covered pixels and at lagging ones.
# A sequence's viewer (data with several frames, CONTRACT §10): the samples are spread over its
# first, middle and last frame, each with its sequence frame number ("frame"), and the viewer's
# frame numbers are listed ("frames") for the slider check.
#
#   exr_samples.py PAGE.html COUNT OUT.json
import json, os, re, sys

import numpy as np
import OpenImageIO as oiio


def channels(path, names):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(f"exr_samples.py: {path}: {buf.geterror()}")
    pixels = buf.get_pixels(oiio.FLOAT)  # (h, w, channels), float32
    spec = buf.spec()
    return {n: pixels[:, :, spec.channelindex(n)] for n in names}


def record(page_dir, script):
    # viewer-data/NAME.js names the EXR(s) it came from: "source": [...], one per frame. Its record
    # is line 2 (compact data's byte string, line 3, is not UTF-8: read as latin-1).
    line2 = open(os.path.join(page_dir, script), encoding="latin-1").read().split("\n")[1]
    return json.loads(line2[line2.index("]=") + 2:].rstrip().rstrip(";"))


def source(page_dir, script):
    return record(page_dir, script)["source"][0]


def mosaic_of(page_dir, html, b, samples):
    # The static image inside this viewer: the first <img class="mosaic"> after its opening tag,
    # before the next viewer's.
    at = html.index(f'data-b="{b}"')
    end = html.find('class="aoeval-viewer"', at)
    m = re.search(r'<img class="mosaic" src="([^"]+)"', html[at:end if end >= 0 else len(html)])
    if not m:
        return None
    path = os.path.join(page_dir, m.group(1))
    inp = oiio.ImageInput.open(path)
    if not inp:
        sys.exit(f"exr_samples.py: {path}: {oiio.geterror()}")
    described = inp.spec().getattribute("aoeval:mosaic")
    inp.close()
    if not described:
        sys.exit(f"exr_samples.py: {path}: no aoeval:mosaic description")
    d = json.loads(described)
    rgb = oiio.ImageBuf(path).get_pixels(oiio.UINT8)[:, :, :3]
    out = {"png": m.group(1), "p99": d["p99"], "scale": d["scale"], "labels": d["labels"],
           "source": d["source"]}
    # Pixel for pixel only (a mosaic wider than 4096 pixels has its panels resized).
    same_size = all(d["panels"][k][2:] == d["source"] for k in ("abs", "signed"))
    for k in ("abs", "signed"):
        x0, y0, w, h = d["panels"][k]
        out[k] = [rgb[y0 + s["y"], x0 + s["x"]].tolist() for s in samples] if same_size else None
        bx, by, bw, bh = d["bars"][k]
        out[k + "_bar"] = {"low": rgb[by + bh - 1, bx + bw // 2].tolist(),
                           "high": rgb[by, bx + bw // 2].tolist()}
    return out


def main():
    page, count, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    page_dir = os.path.dirname(os.path.abspath(page))
    html = open(page).read()
    viewers = re.findall(r'<div class="aoeval-viewer" data-kind="compare" data-a="([^"]+)" data-b="([^"]+)"', html)
    gbuffers = re.findall(r'<div class="aoeval-viewer" data-kind="gbuffer" data-a="([^"]+)"', html)
    maps = re.findall(r'<div class="aoeval-viewer" data-kind="maps" data-a="([^"]+)"', html)
    if not viewers and not gbuffers:
        sys.exit(f"exr_samples.py: {page}: no viewer")
    rng = np.random.default_rng(33)
    result = []
    names = ["Z", "N.X", "N.Y", "N.Z"]
    for a in gbuffers:
        g = channels(os.path.join(page_dir, source(page_dir, a)), names + ["A"])
        ys, xs = np.nonzero(g["A"] > 0.5)
        pick = rng.choice(len(xs), size=min(count, len(xs)), replace=False)
        samples = [dict({"x": int(xs[k]), "y": int(ys[k])},
                        **{n: float(g[n][ys[k], xs[k]]) for n in names}) for k in pick]
        result.append({"a": a, "kind": "gbuffer", "samples": samples})
    for a in maps:  # a sequence point's flicker and lag maps (maps.exr)
        g = channels(os.path.join(page_dir, source(page_dir, a)), ["flicker", "lag", "A"])
        ys, xs = np.nonzero(g["A"] > 0.5)
        pick = rng.choice(len(xs), size=min(count, len(xs)), replace=False)
        # the lagging pixels too: where the lag map is not 0, if any
        lys, lxs = np.nonzero((g["A"] > 0.5) & (g["lag"] > 0))
        pick_lag = rng.choice(len(lxs), size=min(count // 4, len(lxs)), replace=False)
        points = [(int(xs[k]), int(ys[k])) for k in pick] + [(int(lxs[k]), int(lys[k])) for k in pick_lag]
        samples = [{"x": x, "y": y, "flicker": float(g["flicker"][y, x]), "lag": float(g["lag"][y, x])}
                   for x, y in points]
        result.append({"a": a, "kind": "maps", "samples": samples})
    for a, b in viewers:
        ra, rb = record(page_dir, a), record(page_dir, b)
        n = len(ra["source"])
        if len(rb["source"]) != n:
            sys.exit(f"exr_samples.py: {a} has {n} frames, {b} {len(rb['source'])}")
        numbers = ra.get("frame_numbers", list(range(n)))
        picks = sorted({0, n // 2, n - 1})
        samples, focus = [], None
        for i in picks:
            ref = channels(os.path.join(page_dir, ra["source"][i]), ["AO", "AO_stderr", "A"])
            est = channels(os.path.join(page_dir, rb["source"][i]), ["AO", "A"])
            covered = (ref["A"] > 0.5) & (est["A"] > 0.5)
            ys, xs = np.nonzero(covered)
            if focus is None:
                dark = np.argmin(np.where(covered, ref["AO"], np.inf))
                focus = {"x": int(dark % ref["AO"].shape[1]), "y": int(dark // ref["AO"].shape[1])}
            pick = rng.choice(len(xs), size=min(max(1, count // len(picks)), len(xs)), replace=False)
            for k in pick:
                x, y = int(xs[k]), int(ys[k])
                r, e, s = ref["AO"][y, x], est["AO"][y, x], ref["AO_stderr"][y, x]
                # float32 values as exact doubles; the error subtracted in float32, as the EXRs would.
                sample = {"x": x, "y": y, "reference": float(r), "estimate": float(e),
                          "error": float(np.float32(e) - np.float32(r)), "stderr": float(s)}
                if n > 1:
                    sample["frame"] = numbers[i]
                samples.append(sample)
        entry = {"a": a, "b": b, "samples": samples, "focus": focus}
        if n > 1:
            entry["frames"] = numbers
        else:
            mosaic = mosaic_of(page_dir, html, b, samples)
            if mosaic:
                entry["mosaic"] = mosaic
        result.append(entry)
    with open(out, "w") as f:
        json.dump(result, f)


main()
