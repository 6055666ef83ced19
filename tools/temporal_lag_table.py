#!/usr/bin/env python3
"""Must-show 1 of issue 43 from sweep folders: per sequence point, rmse_excess at frame 8 and at
the last frame (their ratio: drift when above 1.05) and lag_rmse_excess, for one folder or for a
before and an after folder of the same spec (joined by run name, so the same seeds).

The cycle column compares whole cycles instead of two frames: the rms of rmse_excess over frames
6..11 (the 6-frame rotation cycle of gtao's `rotations` 6 that holds frame 8) against the rms over
the last 6 frames. A 1-slice gtao frame's error depends on its rotation (on roll at 320x240, frame
8's rotation gives 0.038 and the cycle's rms is 0.070), so frame 8 against the last frame compares
two rotations as much as two moments of the history; the cycle ratio of an estimator with history
against that of the same estimator without history is what its history adds to the content's own
growth of error (README, "Drift: what the frame-8 ratio can show").

  build/aoeval sweep harness/specs/temporal-lag-table.json --out out/lag-before   # main's defaults
  build/aoeval sweep harness/specs/temporal-lag-table.json --out out/lag-after    # tuned defaults
  tools/temporal_lag_table.py out/lag-before out/lag-after
"""
import csv
import json
import os
import sys


def read(folder):
    rows = json.load(open(os.path.join(folder, "results.json")))["rows"]
    out = {}
    for r in rows:
        if r.get("seq_frames") is None:
            continue
        stem = os.path.splitext(os.path.basename(r["estimate_file"]))[0]
        frames = list(csv.DictReader(open(os.path.join(folder, "sequences", stem, "frames.csv"))))
        e = [float(f["rmse_excess"]) for f in frames]
        out[r["run_name"]] = {"f8": e[8], "last": e[-1], "lag": r["lag_rmse_excess"],
                              "steady": r["steady_rmse_excess"],
                              "cycle": (rms(e[6:12]), rms(e[-6:]))}
    return out


def rms(values):
    return (sum(v * v for v in values) / len(values)) ** 0.5


def cell(m):
    lag = "blank" if m["lag"] is None else "%.4f" % m["lag"]
    early, late = m["cycle"]
    return "%.4f/%.4f (%.3f), lag %s, steady %.4f, cycle %.4f/%.4f (%.3f)" % (
        m["f8"], m["last"], m["last"] / m["f8"], lag, m["steady"], early, late, late / early)


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write("usage: temporal_lag_table.py BEFORE_DIR [AFTER_DIR]\n")
        return 2
    before = read(argv[1])
    after = read(argv[2]) if len(argv) == 3 else {}
    head = "| point | frame 8 / last (ratio), lag, steady, cycle 6..11 / last 6 (ratio)" + (
        " before | after | lag after / before |" if after else " |")
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    for name in sorted(before, key=lambda n: (n.split("/scene:")[1], n)):
        line = "| %s | %s |" % (name, cell(before[name]))
        if after:
            a = after.get(name)
            ratio = ("%.3f" % (a["lag"] / before[name]["lag"])
                     if a and a["lag"] and before[name]["lag"] else "")
            line += " %s | %s |" % (cell(a) if a else "", ratio)
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
