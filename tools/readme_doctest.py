#!/usr/bin/env python3
"""The README kept true by a test: every command of README.md's ```sh blocks runs.

    tools/readme_doctest.py --aoeval build/aoeval [--readme README.md] [--keep DIR]

Every ```sh block runs, in README order, line by line (a line ending in a backslash continues), in
one temporary folder laid out like a checkout: `build/aoeval` there is a wrapper around the real
binary, `run.sh` is the repository's own with its bootstrap (apt, cmake) stubbed out (test.sh has
just done both), AOEVAL_CACHE is the folder's own. A command that exits non-zero fails the test,
named by its README line. What makes it fit in about a minute is explicit, in SMALL below, applied
by the wrapper to the command line it is given:

  - a suite, sweep or tune spec (`run --suite quick|default|paper|FILE`, `sweep SPEC`, `tune SPEC`)
    runs its own file, shrunk: a suite's first 2 specs, each at its first scene and view, 32x24,
    16-spp references, one timed repetition, at most 2 runs, each grid axis cut to its first
    value (the runs of an estimator that --set names kept too), tune at 4 evaluations;
  - `reference`, `estimate`, `gbuffer`, `bench reference|estimators|scale`: --res 32x24 unless
    given, --spp at most 16, one repetition, a small accuracy part; the bench's estimators
    BENCH_ESTIMATORS unless --estimator is given; 1 and 2 trees;
  - `figures` runs with --quick, `--all` as its first FIGURES figures; `dashboard` with
    --no-charts and, unless it names --config, a thresholds file with timing left out (two runs'
    times are noise, never a verdict here).

README words the test supplies: RUN_ID (after --baseline the run before the newest in
out/results.sqlite, elsewhere the newest), my-suite.json and my-thresholds.json (FIXTURES below); a ```json block preceded by
`<!-- doctest: file NAME -->` is written to NAME instead of run. A block that cannot run here is
preceded by `<!-- doctest: skip REASON -->`; the test prints how many were skipped and why. A
command of `build/aoeval`, `./run.sh` or `./test.sh` outside a ```sh block (an indented block)
fails the test: it would go unchecked. `./test.sh` is not run (it runs this test), and is
counted among the skipped.
"""
import argparse
import json
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RES = [32, 24]
SPP = 16
SMALL_SPEC = {"scenes": 1, "views": 1, "runs": 2, "evaluations": 4, "specs": 2}
BENCH_ESTIMATORS = ["raytraced", "hbao-split-cpu", "gtao"]  # a CPU pair and a Vulkan one
FIGURES = 2  # `figures --all`: the first ones (figures_cli_test runs each at --quick)
COMMAND = re.compile(r"^\s*(build/aoeval|\./run\.sh|\./test\.sh)\b")
FIXTURES = {
    "my-suite.json": [{"name": "mine", "scenes": ["cornell-box"],
                       "reference": {"spp": 16, "sampler": "sobol"},
                       "runs": [{"estimator": "constant"}, {"estimator": "raytraced"}]}],
    "my-thresholds.json": {"comment": "readme doctest", "defaults": {"time_relative": 1000}},
    "no-timing.json": {"comment": "readme doctest: times are noise here",
                       "defaults": {"time_relative": 1000}},
}


# ---- the wrapper: one aoeval command line made small (SMALL) -------------------------------

def shrink_spec(spec, keep=()):
    """One sweep or tune spec at the doctest's size; the runs of the estimators in `keep` (those
    the command line's --set names) are kept beside the first ones."""
    spec = dict(spec)
    for key in ("scenes", "views"):
        if isinstance(spec.get(key), list):
            spec[key] = spec[key][:SMALL_SPEC[key]]
    spec["res"] = RES
    ref = dict(spec.get("reference", {}))
    ref["spp"] = min(int(ref.get("spp", SPP)), SPP)
    ref.pop("target_stderr", None)
    spec["reference"] = ref
    spec["timing"] = {"warmup": 0, "repetitions": 1}
    if isinstance(spec.get("runs"), list):
        runs = []
        for n, run in enumerate(spec["runs"]):
            if n >= SMALL_SPEC["runs"] and run.get("estimator") not in keep:
                continue
            run = dict(run)
            if isinstance(run.get("grid"), dict):
                run["grid"] = {k: [v["range"][0]] if isinstance(v, dict) and "range" in v
                               else v[:1] if isinstance(v, list) else v
                               for k, v in run["grid"].items()}
            runs.append(run)
        spec["runs"] = runs
    if isinstance(spec.get("tune"), dict):
        spec["tune"] = dict(spec["tune"], evaluations=min(
            int(spec["tune"].get("evaluations", 4)), SMALL_SPEC["evaluations"]))
    return spec


def small_spec_file(path, suite=False, keep=()):
    """The shrunk copy of a spec (or a suite: a list of specs) in .small/, by the same name."""
    if suite and not os.path.exists(path) and "/" not in path and not path.endswith(".json"):
        path = os.path.join(REPO, "harness", "suites", path + ".json")
    elif not os.path.exists(path):
        path = os.path.join(REPO, path)  # harness/specs/... of the checkout
    with open(path) as f:
        text = re.sub(r"^\s*//.*$", "", f.read(), flags=re.M)
    spec = json.loads(text)
    if isinstance(spec, list):
        spec = [shrink_spec(s, keep) for n, s in enumerate(spec)
                if n < SMALL_SPEC["specs"] or any(r.get("estimator") in keep
                                                  for r in s.get("runs", []))]
    else:
        spec = shrink_spec(spec, keep)
    os.makedirs(".small", exist_ok=True)
    out = os.path.join(".small", os.path.basename(path))
    with open(out, "w") as f:
        json.dump(spec, f)
    return out


def option(args, name):
    return any(a == name or a.startswith(name + "=") for a in args)


def small_args(args):
    """SMALL: the command line the wrapper runs instead of `args`."""
    args = list(args)
    if not args:
        return args
    for i, a in enumerate(args[:-1]):
        if a == "--spp":
            args[i + 1] = str(min(int(args[i + 1]), SPP))
    sub = args[0]
    two = " ".join(args[:2])
    res = [] if option(args, "--res") else ["--res", "%dx%d" % tuple(RES)]
    keep = {args[i + 1].split(":")[0] for i, a in enumerate(args[:-1]) if a == "--set"}
    if sub == "run":
        if option(args, "--suite"):
            i = args.index("--suite")
            args[i + 1] = small_spec_file(args[i + 1], suite=True, keep=keep)
        else:
            args += ["--suite", small_spec_file("default", suite=True)]
    elif sub in ("sweep", "tune"):
        spec = next(i for i, a in enumerate(args[1:], 1) if not a.startswith("-"))
        args[spec] = small_spec_file(args[spec])
    elif sub in ("reference", "estimate", "gbuffer"):
        args += res
    elif two == "bench reference":
        args += res + ["--repetitions", "1", "--accuracy-res", "16x12", "--truth-spp", "256"]
        if not option(args, "--spp"):
            args += ["--spp", str(SPP)]
    elif two == "bench estimators":
        args += res + ["--repetitions", "1", "--warmup", "0"]
        if not option(args, "--estimator"):
            for e in BENCH_ESTIMATORS:
                args += ["--estimator", e]
    elif two == "bench scale":
        args += res + ["--repetitions", "1", "--counts", "1", "2"]
        if not option(args, "--spp"):
            args += ["--spp", str(SPP)]
    elif sub == "figures" and not option(args, "--list"):
        if "--all" in args:
            listed = subprocess.run([REAL[0], "figures", "--list"], stdout=subprocess.PIPE,
                                    text=True, check=True).stdout.split("\n")
            names = [l.split()[0] for l in listed if l.strip()][:FIGURES]
            args = [a for a in args if a != "--all"] + names
        args += [] if option(args, "--quick") else ["--quick"]
    elif sub == "dashboard":
        args += ["--no-charts"] if not option(args, "--no-charts") else []
        if not option(args, "--config"):
            args += ["--config", "no-timing.json"]
    return args


REAL = [None]  # the real binary, in the wrapper


def as_aoeval(real, args):
    REAL[0] = real
    os.execv(real, [real] + small_args(args))


# ---- the test: README blocks, run in order ------------------------------------------------

def blocks(readme_lines):
    """(first line number, language, directive, lines) of every fenced block; and the indented
    command lines (outside fences) that would go unchecked."""
    out, loose = [], []
    fence, directive, start, body = None, None, 0, []
    for n, line in enumerate(readme_lines, 1):
        if fence is None:
            m = re.match(r"^```(\w*)\s*$", line)
            if m:
                fence, start, body = m.group(1), n + 1, []
                continue
            d = re.match(r"^<!-- doctest: (skip|file) (.*?) -->\s*$", line)
            if d:
                directive = (d.group(1), d.group(2))
            elif line.strip():
                directive = None if not line.startswith("<!--") else directive
            if line.startswith("    ") and COMMAND.match(line):
                loose.append(n)
        elif line.startswith("```"):
            out.append((start, fence, directive, body))
            fence, directive = None, None
        else:
            body.append(line)
    return out, loose


def commands(start, body):
    """(README line, command) of a block, backslash continuations joined."""
    out, pending, first = [], "", 0
    for n, line in enumerate(body, start):
        if not pending:
            first = n
        pending += line.rstrip()
        if pending.endswith("\\"):
            pending = pending[:-1] + " "
            continue
        if pending.strip() and not pending.strip().startswith("#"):
            out.append((first, pending.strip()))
        pending = ""
    return out


def run_ids(folder):
    db = os.path.join(folder, "out", "results.sqlite")
    if not os.path.exists(db):
        return []
    with sqlite3.connect(db) as c:
        rows = c.execute("SELECT run_id FROM runs ORDER BY started DESC, rowid DESC").fetchall()
    return [r[0] for r in rows]


def set_up(folder, aoeval):
    os.makedirs(os.path.join(folder, "build"))
    os.makedirs(os.path.join(folder, "tools"))
    wrapper = os.path.join(folder, "build", "aoeval")
    with open(wrapper, "w") as f:
        f.write('#!/bin/sh\nexec python3 %s --as-aoeval %s "$@"\n'
                % (os.path.abspath(__file__), os.path.abspath(aoeval)))
    stub = os.path.join(folder, "tools", "bootstrap.sh")
    with open(stub, "w") as f:
        f.write("#!/bin/sh\n# readme doctest: apt and the build are test.sh's, done already\n")
    for path in (wrapper, stub):
        os.chmod(path, 0o755)
    shutil.copy(os.path.join(REPO, "run.sh"), folder)
    for name, content in FIXTURES.items():
        with open(os.path.join(folder, name), "w") as f:
            json.dump(content, f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--aoeval", required=True)
    ap.add_argument("--readme", default=os.path.join(REPO, "README.md"))
    ap.add_argument("--keep", help="run in this (new) folder and keep it")
    a = ap.parse_args()
    with open(a.readme) as f:
        lines = f.read().split("\n")
    found, loose = blocks(lines)
    failures = ["%s:%d: a command outside a ```sh block (not checked): %s"
                % (a.readme, n, lines[n - 1].strip()) for n in loose]
    folder = a.keep or tempfile.mkdtemp(prefix="readme_doctest_")
    if a.keep:
        os.makedirs(a.keep)
    set_up(folder, a.aoeval)
    env = dict(os.environ, AOEVAL_CACHE=os.path.join(folder, "cache"))
    for start, lang, directive, body in found:  # the README's files first: commands name them
        if directive and directive[0] == "file":
            with open(os.path.join(folder, directive[1]), "w") as f:
                f.write("\n".join(body) + "\n")
    ran, skipped, began = 0, [], time.monotonic()
    for start, lang, directive, body in found:
        if directive and directive[0] == "skip":
            skipped.append("%s:%d: %s" % (a.readme, start - 1, directive[1]))
            continue
        if lang != "sh" or directive:
            continue
        for n, command in commands(start, body):
            if command.startswith("./test.sh"):
                skipped.append("%s:%d: ./test.sh runs the test suite this test is part of" %
                               (a.readme, n))
                continue
            ids = run_ids(folder)
            if "RUN_ID" in command and len(ids) >= 2:
                command = command.replace("--baseline RUN_ID", "--baseline " + ids[1])
                command = command.replace("RUN_ID", ids[0])
            t = time.monotonic()
            p = subprocess.run(["bash", "-c", command], cwd=folder, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=300)
            ran += 1
            print("%s:%d: exit %d, %.1f s: %s" % (a.readme, n, p.returncode,
                                                  time.monotonic() - t, command), flush=True)
            if p.returncode != 0:
                tail = "\n    ".join(p.stdout.strip().split("\n")[-8:])
                failures.append("%s:%d: exit %d: %s\n    %s"
                                % (a.readme, n, p.returncode, command, tail))
    print("readme doctest: %d commands run in %.0f s, %d failed; %d blocks skipped%s"
          % (ran, time.monotonic() - began, len(failures), len(skipped),
             "".join("\n  skipped " + s for s in skipped)))
    for f in failures:
        print("FAILED " + f)
    if not a.keep:
        shutil.rmtree(folder, ignore_errors=True)
    return 1 if failures or ran == 0 else 0


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--as-aoeval":
        as_aoeval(sys.argv[2], sys.argv[3:])
    sys.exit(main())
