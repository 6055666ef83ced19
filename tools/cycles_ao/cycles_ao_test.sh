#!/usr/bin/env bash
# ctest cycles_ao_test: `aoeval reference` against Blender Cycles' AO pass (tools/cycles_ao/
# compare.py). First what the pass means: 1 on an open plane, 0 inside a closed box, then a box at
# dmax 0.5 and the Quake 3 level oa-dm4/hall at dmax 1 (the level is closed, so unbounded AO is 0
# everywhere there), each mean within 4 standard errors. Last, a planted wrong set-up must fail:
# Cycles' box pixel filter (1 px wide) on the plane's silhouette. Skipped (77) without blender.
# Usage: cycles_ao_test.sh AOEVAL WORKDIR
set -uo pipefail
aoeval="$1"
work="$2"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
command -v blender >/dev/null || { echo "SKIP: blender is not installed (Debian package blender)"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
compare() { /usr/bin/python3 "$here/compare.py" --aoeval "$aoeval" --res 64x48 "$@"; }
fail=0
check() {
  local name="$1" want="$2"
  shift 2
  compare --work "$work/$name" --json "$work/$name.json" "$@" >"$work/$name.log" 2>&1
  local rc=$?
  if [ "$rc" -ne "$want" ]; then
    echo "FAIL $name: exit $rc, expected $want"
    cat "$work/$name.log"
    fail=1
  else
    echo "ok   $name (exit $rc): $(grep -E '"(mean_ours|mean_cycles|z|fractional_alpha_per_silhouette_pixel)"' "$work/$name.log" | tr -d ' \n')"
  fi
}
check plane 0 --scene "$here/open_plane.json" --spp 64 --cycles-spp 64 --expect 1
check box 0 --scene "$here/closed_box.json" --spp 64 --cycles-spp 64 --expect 0
check box_dmax 0 --scene "$here/closed_box.json" --spp 256 --cycles-spp 256 --dmax 0.5
check level 0 --scene oa-dm4 --view hall --spp 256 --cycles-spp 256 --dmax 1
check planted_box_filter 1 --scene "$here/open_plane.json" --spp 16 --cycles-spp 16 --pixel-filter BOX
exit "$fail"
