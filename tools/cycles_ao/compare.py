#!/usr/bin/python3
"""`aoeval reference` against Blender Cycles' AO pass of the same view (issue 44, must-show 2).

    tools/cycles_ao/compare.py --aoeval build/aoeval --scene oa-dm4 --view hall --res 160x120 \
        --spp 256 --cycles-spp 256 --dmax inf --work /tmp/cycles [--json verdict.json]

Steps: `aoeval scenes export` writes the triangles as the reference traces them and the view's
camera; `aoeval gbuffer` and `aoeval reference --weighting cosine --normal geometric` compute ours;
Blender renders Cycles' AO pass twice (seeds 1 and 2, tools/cycles_ao/render_ao.py says what the
pass is and how its conventions are matched). Compared pixels: covered in both (our A = 1, Cycles'
alpha = 1) and hitting the same point (Cycles' Position pass, written from its first sample, within
1e-4 of the scene's extent of our G-buffer P: this checks the camera, the pixel centre and y). A
pixel with fractional alpha (some samples hit, some missed) means samples off the pixel centre: a
filter w px wide gives about w fractional pixels per silhouette pixel (covered, with an uncovered
neighbour), so more than 0.05 of them (5x the 0.01 px asked for) fails the check; Cycles' box
filter, 1 px wide, gives about 1.

Verdict: d = mean(ours) - mean(Cycles) over the compared pixels; its standard error is
sqrt(SE_ours^2 + SE_cycles^2) with SE_ours = sqrt(sum AO_stderr^2) / n (the reference's own
per-pixel standard errors) and SE_cycles = sqrt(sum (c1 - c2)^2 / 4) / n (two independent seeds:
the variance of their mean is E[(c1 - c2)^2] / 4 per pixel). Pass when |d| <= 4 SE. Also printed:
the per-pixel chi^2 / n of (ours - Cycles) against the two variances (about 1 when the images agree
pixel by pixel, not only on average), and the Position check.

Exit 0 when it passes, 1 when it does not, 2 on bad usage, 77 when blender is not installed.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))


def read_channels(path, names):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"compare.py: cannot read {path}: {oiio.geterror()}")
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
    inp.close()
    pixels = pixels.reshape(spec.height, spec.width, spec.nchannels)
    out = {}
    for name in names:
        match = [k for k, c in enumerate(spec.channelnames) if c == name or c.endswith("." + name)]
        if not match:
            sys.exit(f"compare.py: {path} has no channel {name} ({spec.channelnames})")
        out[name] = pixels[:, :, match[0]].astype(np.float64)
    return out


def run(cmd):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        sys.stderr.write(result.stdout[-4000:])
        sys.exit(f"compare.py: failed ({result.returncode}): {' '.join(cmd)}")
    return result.stdout


def render_cycles(a, work, seed):
    out = os.path.join(work, f"cycles_seed{seed}.exr")
    distance = "1e30" if a.dmax == "inf" else a.dmax
    cmd = [a.blender, "--background", "--factory-startup", "--python",
           os.path.join(HERE, "render_ao.py"), "--", "--ply", os.path.join(work, "scene.ply"),
           "--camera", os.path.join(work, "camera.json"), "--spp", str(a.cycles_spp),
           "--seed", str(seed), "--distance", distance, "--out", out]
    if a.threads:
        cmd += ["--threads", str(a.threads)]
    cmd += ["--pixel-filter", a.pixel_filter]
    run(cmd)
    return read_channels(out, ["AO.R", "Combined.A", "Position.X", "Position.Y", "Position.Z"])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--aoeval", required=True)
    p.add_argument("--scene", required=True)
    p.add_argument("--view", default="")
    p.add_argument("--res", default="160x120")
    p.add_argument("--spp", type=int, default=256, help="the reference's rays per pixel")
    p.add_argument("--cycles-spp", type=int, default=256, help="Cycles' samples per seed")
    p.add_argument("--dmax", default="inf", help="AO range (Cycles' world AO distance), or inf")
    p.add_argument("--blender", default=shutil.which("blender") or "")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--pixel-filter", default="GAUSSIAN", choices=["GAUSSIAN", "BOX"],
                   help="Cycles' pixel filter: BOX (1 px wide) only to see the check fail")
    p.add_argument("--work", required=True, help="folder for the intermediate files")
    p.add_argument("--json", default="", help="write the verdict here too")
    p.add_argument("--expect", type=float, default=None,
                   help="also require both means within 1e-6 of this value (1: open plane, 0: "
                        "closed box)")
    a = p.parse_args()
    if not a.blender or not os.path.exists(a.blender):
        print("SKIP: blender is not installed (Debian package blender; tools/bootstrap.sh --test)")
        return 77
    os.makedirs(a.work, exist_ok=True)
    view = ["--view", a.view] if a.view else []
    common = ["--scene", a.scene, *view, "--res", a.res]
    run([a.aoeval, "scenes", "export", a.scene, *view, "--res", a.res,
         "--out", os.path.join(a.work, "scene.ply"),
         "--camera", os.path.join(a.work, "camera.json")])
    run([a.aoeval, "gbuffer", *common, "-o", os.path.join(a.work, "gbuffer.exr")])
    run([a.aoeval, "reference", *common, "--spp", str(a.spp), "--weighting", "cosine",
         "--dmax", a.dmax, "--normal", "geometric", "--no-cache",
         "-o", os.path.join(a.work, "reference.exr")])
    g = read_channels(os.path.join(a.work, "gbuffer.exr"), ["A", "P.X", "P.Y", "P.Z"])
    ref = read_channels(os.path.join(a.work, "reference.exr"), ["AO", "AO_stderr", "A"])
    c1, c2 = render_cycles(a, a.work, 1), render_cycles(a, a.work, 2)

    p_ours = np.stack([g["P.X"], g["P.Y"], g["P.Z"]], -1)
    p_cyc = np.stack([c1["Position.X"], c1["Position.Y"], c1["Position.Z"]], -1)
    covered = (ref["A"] == 1) & (c1["Combined.A"] > 0.999) & (c2["Combined.A"] > 0.999)
    extent = float(np.ptp(p_ours[g["A"] == 1].reshape(-1, 3), axis=0).max()) or 1.0
    gap = np.linalg.norm(p_ours - p_cyc, axis=-1) / extent
    same_point = covered & (gap <= 1e-4)
    n = int(same_point.sum())
    coverage_mismatch = int(((ref["A"] == 1) != (c1["Combined.A"] > 0.5)).sum())
    fractional_alpha = int(sum(((c["Combined.A"] > 0) & (c["Combined.A"] < 1)).sum()
                               for c in (c1, c2)))
    mine = np.pad(ref["A"] == 1, 1, mode="edge")
    silhouette = int((mine[1:-1, 1:-1] & ~(mine[:-2, 1:-1] & mine[2:, 1:-1] & mine[1:-1, :-2] &
                                          mine[1:-1, 2:])).sum())
    fractional_share = (fractional_alpha / (2 * silhouette) if silhouette
                        else float(fractional_alpha))
    if n == 0:
        print("compare.py: no pixel is covered by both images at the same point")
        return 1

    ours, ours_se = ref["AO"][same_point], ref["AO_stderr"][same_point]
    a1, a2 = c1["AO.R"][same_point], c2["AO.R"][same_point]
    cyc = 0.5 * (a1 + a2)
    cyc_var = (a1 - a2) ** 2 / 4.0
    se_ours = math.sqrt(float((ours_se ** 2).sum())) / n
    se_cyc = math.sqrt(float(cyc_var.sum())) / n
    se = math.hypot(se_ours, se_cyc)
    d = float(ours.mean() - cyc.mean())
    # Per pixel: Cycles' variance of the two-seed mean, from the binomial bound p(1-p)/(2 N) (its
    # PMJ samples are stratified, so this is an upper bound), keeps chi2 finite on 0/1 pixels.
    p_hat = np.clip(cyc, 0, 1)
    var_pixel = ours_se ** 2 + p_hat * (1 - p_hat) / (2 * a.cycles_spp)
    ok = var_pixel > 0
    chi2 = float(((ours - cyc)[ok] ** 2 / var_pixel[ok]).mean()) if ok.any() else 0.0
    verdict = {
        "scene": a.scene, "view": a.view, "res": a.res, "dmax": a.dmax, "spp": a.spp,
        "cycles_spp_per_seed": a.cycles_spp, "pixels": n,
        "covered_not_same_point": int((covered & ~same_point).sum()),
        "coverage_mismatch_pixels": coverage_mismatch,
        "fractional_alpha_pixels": fractional_alpha,
        "silhouette_pixels": silhouette,
        "fractional_alpha_per_silhouette_pixel": fractional_share,
        "position_gap_rel_median": float(np.median(gap[covered])),
        "position_gap_rel_p99": float(np.percentile(gap[covered], 99)),
        "mean_ours": float(ours.mean()), "mean_cycles": float(cyc.mean()),
        "mean_cycles_seed1": float(a1.mean()), "mean_cycles_seed2": float(a2.mean()),
        "difference": d, "se_ours": se_ours, "se_cycles": se_cyc, "se": se,
        "z": d / se if se > 0 else (0.0 if d == 0 else math.inf),
        "rms_pixel_difference": float(np.sqrt(((ours - cyc) ** 2).mean())),
        "chi2_per_pixel": chi2,
    }
    passed = abs(d) <= 4 * se and fractional_share <= 0.05
    if a.expect is not None:
        passed = (passed and abs(ours.mean() - a.expect) <= 1e-6
                  and abs(cyc.mean() - a.expect) <= 1e-6)
        verdict["expect"] = a.expect
    verdict["passed"] = bool(passed)
    text = json.dumps(verdict, indent=2)
    print(text)
    if a.json:
        with open(a.json + ".tmp", "w") as f:
            f.write(text + "\n")
        os.replace(a.json + ".tmp", a.json)
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
