#!/usr/bin/env bash
# `aoeval sweep --slurm` on a real one-node Slurm cluster (issue 19, CONTRACT §9):
#  1. a tiny sweep submitted with --slurm (reference stage, 2 cost-balanced shards, merge job) is
#     merged into the same rows, with the same metric bits, as the same sweep on one machine, and
#     the merged rows are appended to SQLite;
#  2. a shard that fails (its folder is held by another process) makes the merge job fail with a
#     message naming the shard, and the finished shard keeps its rows;
#  3. --slurm --resume resubmits only the failed shard, and the merge then completes, equal to 1.
# Usage: slurm_cluster_test.sh AOEVAL_BINARY. Exit 77 (skipped) when Slurm cannot be installed.
set -uo pipefail
aoeval="$(realpath "$1")"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d "${TMPDIR:-/tmp}/aoeval_slurm_XXXXXX")"
source "$here/testing/one_node_slurm.sh"
holder=""
cleanup() {
  [ -n "$holder" ] && kill "$holder" 2>/dev/null
  slurm_stop
  [ -e "$work/.failed" ] || rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  echo "(kept $work)" >&2
  touch "$work/.failed"
  exit 1
}

t0=$SECONDS
slurm_start "$work/cluster" 4
rc=$?
[ $rc -eq 77 ] && exit 77
[ $rc -eq 0 ] || fail "the one-node cluster did not start"
echo "cluster started in $((SECONDS - t0)) s" >&2

export AOEVAL_CACHE="$work/cache"
cd "$work" || exit 1
cat >tiny.json <<'JSON'
{"name": "tiny", "scenes": ["cornell-box"], "res": [24, 24],
 "reference": {"spp": 8, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
 "runs": [{"estimator": "constant", "grid": {"value": [0.2, 0.5, 0.8]}},
          {"estimator": "obscurances", "grid": {"rays": [1, 2, 4]}, "fixed": {"dmax": 0.5}}]}
JSON

# The metric bits and identity of every row, keyed by run name (timings and run ids differ).
rows() {
  python3 - "$1" <<'PY'
import json, sys
rows = json.load(open(sys.argv[1]))["rows"]
drop = {"run_id", "timestamp", "estimate_file", "precompute_ms", "machine"}
for r in sorted(rows, key=lambda r: r["run_name"]):
    print(json.dumps({k: v for k, v in r.items() if k not in drop and not k.startswith("time_ms")},
                     sort_keys=True))
PY
}

# Submits, prints the job ids on stdout (references shards merge), waits for them.
submit_and_wait() {
  local out
  out="$("$aoeval" sweep tiny.json "$@")" || fail "submission failed: $out"
  echo "$out" >&2
  local ids
  ids="$(echo "$out" | sed -n 's/^[a-z]*: job \([0-9]*\).*/\1/p' | paste -sd, -)"
  [ -n "$ids" ] || fail "no job ids printed"
  slurm_wait "$ids" 120 || fail "jobs did not finish"
  echo "$out"
}

"$aoeval" sweep tiny.json --out single --db single.sqlite >/dev/null 2>single.err ||
  fail "single-machine sweep: $(cat single.err)"

# 1. Submitted, merged, equal.
out="$(submit_and_wait --slurm --shards 2 --out cl --db cl.sqlite)" || exit 1
merge_job="$(echo "$out" | sed -n 's/^merge: job \([0-9]*\).*/\1/p')"
[ "$(slurm_job_state "$merge_job")" = COMPLETED ] || fail "merge job: $(cat cl/slurm/logs/merge.log)"
[ "$(echo "$out" | tail -1)" = "$work/cl/results.csv" ] || fail "last line is not the results: $out"
[ -f cl/results.json ] || fail "merge wrote no results.json: $(cat cl/slurm/logs/merge.log)"
diff <(rows single/results.json) <(rows cl/results.json) >&2 || fail "merged rows differ from the single-machine run"
n="$(sqlite3 cl.sqlite "select count(*) from results where run_id = (select run_id from runs where command like 'merge%')")"
[ "$n" = 6 ] || fail "SQLite holds $n merged rows, not 6"
for i in 0 1; do
  [ -s "cl/shards/shard-$i-of-2/shard.json" ] || fail "shard $i wrote no shard.json"
done
grep -q "slowest/mean shard" cl/slurm/logs/merge.log || fail "merge did not quote the shard balance"

# 2. Shard 1's folder is held by another process: shard 1 fails, the merge job fails naming it.
mkdir -p fl/shards/shard-1-of-2
# The holder execs into sleep, so its pid is the lock's only holder and killing it frees the lock.
(exec 9>fl/shards/shard-1-of-2/.aoeval.lock && flock 9 && exec sleep 300) >/dev/null 2>&1 &
holder=$!
out="$(submit_and_wait --slurm --shards 2 --out fl --db fl.sqlite)" || exit 1
merge_job="$(echo "$out" | sed -n 's/^merge: job \([0-9]*\).*/\1/p')"
[ "$(slurm_job_state "$merge_job")" = FAILED ] || fail "the merge job did not fail: $(slurm_job_state "$merge_job")"
grep -q "incomplete: shard 1 of 2 lacks" fl/slurm/logs/merge.log || fail "merge log: $(cat fl/slurm/logs/merge.log)"
grep -q "another aoeval process" fl/slurm/logs/shard-1.log || fail "shard 1 log: $(cat fl/slurm/logs/shard-1.log)"
[ ! -e fl/results.json ] || fail "a failed merge wrote results"
kept="$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["rows"]))' fl/shards/shard-0-of-2/results.json)"
[ "$kept" -ge 1 ] || fail "the finished shard lost its rows"
kill "$holder"
wait "$holder" 2>/dev/null
holder=""

# 3. --resume: only shard 1 is resubmitted; the merge completes, equal to the single run.
out="$(submit_and_wait --slurm --shards 2 --out fl --db fl.sqlite --resume)" || exit 1
echo "$out" | grep -q "^shards: job [0-9]* (array 1 of 2" || fail "resume resubmitted more than shard 1: $out"
merge_job="$(echo "$out" | sed -n 's/^merge: job \([0-9]*\).*/\1/p')"
[ "$(slurm_job_state "$merge_job")" = COMPLETED ] || fail "merge after resume: $(cat fl/slurm/logs/merge.log)"
diff <(rows single/results.json) <(rows fl/results.json) >&2 || fail "resumed rows differ from the single-machine run"
echo "slurm round trip: ok"
