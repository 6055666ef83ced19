#!/usr/bin/env python3
"""How precise a row's noise-removed scores are, given its reference's noise (issue 42; README
"How precise a reference must be"). rmse_excess^2 = mean((est - ref)^2) - mean(stderr^2) is
unbiased; what the reference's spp buys is its variance. With D the key, s the rms of the
reference's per-pixel stderr over the N compared pixels (independent: each pixel draws its own
scrambled directions), the dashboard's rule (reports/regression.cpp, rmse_excess_sigma):

    sigma(D) = min(s (2/N)^(1/4), s sqrt(D^2 + s^2/2) / (D sqrt(N)))

A sequence's keys pool frames (reports/regression.cpp, metric_noise_sigma): seq_rmse_excess over
N x F pixels, steady_rmse_excess over N x floor(F/2), temporal_rmse_excess over N x (F - 1)
pixel pairs with s -> sqrt(2) s, where F counts the independent references, the row's
seq_reference_frames (1 for a static camera over a static scene, whose frames share one;
seq_frames in rows written before that key); with one reference temporal_rmse_excess holds none
of its noise (SD 0). N and s are the row's own (its last frame's for a sequence).

usage: tools/reference_precision.py ROWS.json                  the SD of each row's keys
       tools/reference_precision.py BEFORE.json AFTER.json     the largest |after - before| in
                                                               units of sqrt(SD_b^2 + SD_a^2)
Rows that carry `<key>_sd` (rmse_excess_sd, seq_rmse_excess_sd, ...: scoring/metrics.h and
temporal.h, the per-pixel form of the rule, which holds where the error concentrates where the
reference is noisy) are judged by it; the rule above is for rows written before those keys.
ROWS.json: a results.json (`aoeval run`/`sweep`). Exit 0; 1 when a difference exceeds 4 SD."""
import json, math, sys

KEYS = ["rmse_excess", "true_rmse_excess", "seq_rmse_excess", "true_seq_rmse_excess",
        "steady_rmse_excess", "true_steady_rmse_excess", "temporal_rmse_excess",
        "true_temporal_rmse_excess"]
# Keys over pixel subsets the row does not count (disoccluded, lagging pixels) and frame counts:
# printed as relative differences, not judged.
SHOWN = ["disocclusion_rmse_excess", "lag_rmse_excess", "converge_frames", "settle_frames"]


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def sd_of(D, s, n):
    """The rule: sigma of a noise-removed rms D over n pixels whose reference noise has rms s."""
    if D is None or s is None or not n or s <= 0:
        return None
    near_zero = s * (2.0 / n) ** 0.25
    if D <= 0:
        return near_zero
    return min(near_zero, s * math.sqrt(D * D + 0.5 * s * s) / (D * math.sqrt(n)))


def precision(row, key):
    # The row's own: rmse_excess_sd and the sequence keys' _sd, taken per pixel at scoring time
    # (the rule below assumes the error does not concentrate where the reference is noisy; it
    # does, and the rule understates the spread up to 2.2x there). The rule for older rows.
    own = num(row.get(key + "_sd"))
    if own is not None and own > 0:  # 0: no stderr (or no noise at all), as the rule says below
        return own
    true = key.startswith("true_")
    p = "true_" if true else ""
    base = key[len(p):]
    n, s = num(row.get(p + "pixels")), num(row.get(p + "ref_stderr_rms"))
    frames = num(row.get(p + "seq_frames")) or num(row.get("seq_frames")) or 1
    # The independent reference images pooled: a frame that repeats frame k-1's reference (a
    # static camera over a static scene, traced once) adds none. Rows from before the key: F.
    traced = num(row.get(p + "seq_reference_frames")) or num(row.get("seq_reference_frames"))
    if traced is not None and traced >= 1:
        frames = min(frames, traced)
    if n is None or s is None:
        return None
    if base == "rmse_excess":
        return sd_of(num(row.get(key)), s, n)
    if base == "seq_rmse_excess":
        return sd_of(num(row.get(key)), s, n * frames)
    if base == "steady_rmse_excess":
        return sd_of(num(row.get(key)), s, n * max(1, frames // 2))
    if base == "temporal_rmse_excess":
        if frames < 2:  # one reference for every frame: the differences hold none of its noise
            return 0.0
        return sd_of(num(row.get(key)), s * math.sqrt(2), n * (frames - 1))
    return None


def load(path):
    doc = json.load(open(path))
    rows = doc["rows"] if isinstance(doc, dict) else doc
    return {r["run_name"]: r for r in rows if r.get("status", "ok") == "ok"}


def main(argv):
    if len(argv) == 2:
        for name, r in sorted(load(argv[1]).items()):
            for k in KEYS:
                sd = precision(r, k)
                if sd is not None and num(r.get(k)) is not None:
                    print(f"{name:70s} {k:26s} {num(r[k]):.5f} +- {sd:.2e}")
        return 0
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    before, after = load(argv[1]), load(argv[2])
    common = sorted(set(before) & set(after))
    print(f"{len(before)} rows before, {len(after)} after, {len(common)} in both")
    worst, judged, over = (0.0, "", ""), 0, 0
    shown = []
    for name in common:
        b, a = before[name], after[name]
        for k in KEYS:
            vb, va = num(b.get(k)), num(a.get(k))
            sb, sa = precision(b, k), precision(a, k)
            if None in (vb, va, sb, sa):
                continue
            z = abs(va - vb) / max(math.hypot(sb, sa), 1e-12)
            judged += 1
            over += z > 4
            if z > worst[0]:
                worst = (z, name, f"{k} {vb:.5f} -> {va:.5f} (SD {sb:.1e} before, {sa:.1e} after)")
        for k in SHOWN:
            vb, va = num(b.get(k)), num(a.get(k))
            if vb is not None and va is not None and vb != va:
                shown.append((abs(va - vb) / max(abs(vb), 1e-12), name, k, vb, va))
    print(f"{judged} values judged; the largest difference is {worst[0]:.2f} SD: {worst[1]} {worst[2]}")
    print(f"{over} beyond 4 SD")
    for rel, name, k, vb, va in sorted(shown, reverse=True)[:10]:
        print(f"  not judged: {name} {k} {vb:g} -> {va:g} ({rel:.1%})")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
