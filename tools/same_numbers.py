#!/usr/bin/env python3
"""Same numbers before and after a move (issue 27): compares two output folders, each holding
quick/ (`aoeval run --suite quick --out DIR/quick`) and figures/ (`aoeval figures --all --quick
--out DIR/figures`) from two binaries. Every value of the suite's results.json rows and of the
figures' CSVs outside timing and provenance columns must be equal (columns only one side has are
listed, not failed); every EXR of quick/ must pass `idiff -fail 0 -warn 0` against its twin (run
ids in paths matched by position). A figure that chooses its settings by measured time (the
equal-time figures) differs with the machine's load: its rows are printed, to be read.

usage: tools/same_numbers.py BEFORE_DIR AFTER_DIR   (exit 0 when the same, 1 when not)"""
import csv, glob, json, os, sys, math, re, subprocess
before, after = sys.argv[1], sys.argv[2]
SKIP = re.compile(r'(^time_|_ms$|_ms_|^ms_|^run_id$|^git_commit$|^timestamp$|^aoeval_version$|^estimator_version$|^machine$|'
                  r'^device$|^estimate_file$|^reference$|^repetitions$|^timing_source$|^started$|^output_dir$|'
                  r'_fps$|^speedup|^budget_ms$|^wall|'
                  # ratios of times and throughputs (dimitrov-table1, hegeman-throughput, mendez-fig7)
                  r'^ho_over_no$|^blur_over_ho$|^relative_to_ambient$|^mpixel_per_s$|^relative_time$)')
# Figures that pick their contenders' settings by measured time: printed, not judged.
TIME_CHOSEN = {'equal-time.csv', 'temporal-equal-time.csv'}
def same(a, b):
    if a == b: return True
    try:
        fa, fb = float(a), float(b)
        return (math.isnan(fa) and math.isnan(fb)) or fa == fb
    except (TypeError, ValueError):
        return False
bad = 0
# quick suite rows
rb = {r['run_name']: r for r in json.load(open(f'{before}/quick/results.json'))['rows']}
ra = {r['run_name']: r for r in json.load(open(f'{after}/quick/results.json'))['rows']}
print(f'quick suite: {len(rb)} rows before, {len(ra)} after; names equal: {set(rb) == set(ra)}')
only_a, only_b, compared = set(), set(), 0
for name in sorted(set(rb) & set(ra)):
    a, b = ra[name], rb[name]
    only_a |= set(a) - set(b); only_b |= set(b) - set(a)
    for k in set(a) & set(b):
        if SKIP.search(k): continue
        compared += 1
        if not same(a[k], b[k]):
            bad += 1
            if bad < 20: print(f'  DIFF {name} {k}: {b[k]!r} -> {a[k]!r}')
print(f'  {compared} values compared; columns only after: {sorted(only_a)}; only before: {sorted(only_b)}')
# figures CSVs
def csv_files(root):
    return sorted(os.path.relpath(os.path.join(d, f), root) for d, _, names in os.walk(root)
                  for f in names if f.endswith('.csv'))
figures_b, figures_a = f'{before}/figures', f'{after}/figures'
csvs, csvs_a = csv_files(figures_b), csv_files(figures_a)
print(f'figures: {len(csvs)} CSVs before, {len(csvs_a)} after; only after: {sorted(set(csvs_a) - set(csvs))}; only before: {sorted(set(csvs) - set(csvs_a))}')
nval = 0; fbad = 0
for rel in csvs:
    if rel not in csvs_a: continue
    B = list(csv.DictReader(open(os.path.join(figures_b, rel)))); A = list(csv.DictReader(open(os.path.join(figures_a, rel))))
    if len(A) != len(B):
        print(f'  ROWS {rel}: {len(B)} -> {len(A)}'); fbad += 1; continue
    for i, (x, y) in enumerate(zip(B, A)):
        for k in set(x) & set(y):
            if SKIP.search(k) or k in ('time', 'ms', 'seconds'): continue
            if rel in TIME_CHOSEN:
                if not same(x[k], y[k]): print(f'  (time-chosen) {rel} row {i} {k}: {x[k]!r} -> {y[k]!r}')
                continue
            nval += 1
            if not same(x[k], y[k]):
                fbad += 1
                if fbad < 60: print(f'  DIFF {rel} row {i} {k}: {x[k]!r} -> {y[k]!r}')
    if A and B and set(A[0]) != set(B[0]):
        print(f'  COLUMNS {rel}: only after {sorted(set(A[0]) - set(B[0]))}, only before {sorted(set(B[0]) - set(A[0]))}')
print(f'  {nval} values compared, {fbad} differ')
# EXRs
exr_n = exr_bad = 0
for path in sorted(glob.glob(f'{before}/quick/**/*.exr', recursive=True)):
    rel = os.path.relpath(path, f'{before}/quick')
    twin = glob.glob(os.path.join(f'{after}/quick', re.sub(r'runs/[0-9TZ]+-[0-9a-f]+/', 'runs/*/', rel)))
    exr_n += 1
    if not twin or subprocess.run(['idiff', '-q', '-fail', '0', '-warn', '0', path, twin[0]],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
        exr_bad += 1
        print(f'  EXR {rel}: {"no twin" if not twin else "differs"}')
print(f'EXRs: {exr_n} compared with idiff -fail 0, {exr_bad} differ')
all_same = bad == 0 and fbad == 0 and exr_bad == 0
print('SAME' if all_same else f'DIFFERENT: {bad} suite values, {fbad} figure values, {exr_bad} EXRs')
sys.exit(0 if all_same else 1)
