#!/usr/bin/env bash
# ctest "browser_injection_test" (reports/CMakeLists.txt, issue 48): every string a user controls
# is planted with script -- the scene (its file name), its views and objects, a plug-in's
# parameter values (a choice parameter), the suite's and the sweep's names -- and the pages built
# from them are opened in Debian's headless chromium by check_injection.js: the suite report, its
# G-buffer gallery, a sequence sweep's page, the dashboard over two runs and the figures index.
# Any dialog, CSP violation or planted element fails. First, the checker must catch one planted
# handler written raw into a copy of a page. Also: views "a<b" and "a>b" (they sanitise alike)
# keep an estimate file each.
#
#   run_injection_test.sh AOEVAL BUILD_DIR
set -euo pipefail
aoeval="$(realpath "$1")"
build="$(realpath "$2")"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
chromium="${AOEVAL_CHROMIUM:-/usr/bin/chromium}"
# shellcheck source=playwright_modules.sh
source "$here/playwright_modules.sh"
modules="$(playwright_modules "$here" "$build" "$chromium")" || exit $?

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export AOEVAL_CACHE="$work/cache"
cd "$work"

# The plants (no '/' where a name becomes a file or folder: the scene, suite and sweep names).
P1='<script>alert(1)</script>'
P2='"><img src=x onerror=alert(2)>'
P3='</script><script>alert(3)</script>'
P4="'><svg onload=alert(4)>"
P5='<img src=x onerror=alert(5)>'
export P1 P2 P3 P4 P5

scene="$work/\"><img src=x onerror=alert(6)>.json"
python3 - "$scene" <<'PY'
import json, os, sys
p = [os.environ[k] for k in ("P1", "P2", "P3", "P4", "P5")]
view = lambda name, x: {"name": name, "eye": [x, 1.2, 1.6], "target": [0, 0.2, 0], "fov_y_deg": 50,
                        "width": 24, "height": 18}
views = [view(p[0], 0.0), view(p[1], 0.1), view("a<b", 0.2), view("a>b", 0.3)]
seq = view(p[3], 0.0)
seq["sequence"] = {"frames": 3, "fps": 10,
                   "camera": [{"frame": 2, "eye": [0.2, 1.2, 1.6], "target": [0, 0.2, 0]}],
                   "objects": {p[4]: [{"frame": 0, "translate": [-0.2, 0, 0]},
                                      {"frame": 2, "translate": [0.2, 0, 0]}]}}
views.append(seq)
json.dump({"objects": [{"name": p[2], "generator": "plane", "params": {"size": [4, 4]}},
                       {"name": p[4], "generator": "box", "params": {"size": [0.5, 0.5, 0.5]}}],
           "views": views}, open(sys.argv[1], "w"))
PY

mkdir -p plugins/planted
cp "$here/../../plugins/examples/constant-copy/constant_copy.py" plugins/planted/
python3 - <<'PY'
import json, os
p = [os.environ[k] for k in ("P1", "P2", "P3", "P4", "P5")]
json.dump({"name": "planted-copy", "summary": p[0], "paper": p[1], "kind": "process",
           "command": ["/usr/bin/python3", "constant_copy.py"],
           "params": [{"name": "value", "type": "real", "default": 0.5, "min": 0, "max": 1,
                       "unit": p[2], "meaning": p[3]},
                      {"name": "mode", "type": "choice", "default": p[0], "choices": p[:3],
                       "meaning": p[4]}],
           "definition": {"weighting": "cosine", "dmax": None, "falloff": "none"},
           "outputs": ["AO"], "timeout_s": 60}, open("plugins/planted/estimator.json", "w"))
views = [p[0], p[1], "a<b", "a>b"]
json.dump([{"name": "'><svg onload=alert(7)>", "scenes": [os.path.abspath(
               '"><img src=x onerror=alert(6)>.json')], "views": views, "res": [24, 18],
            "reference": {"spp": 4, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
            "runs": [{"estimator": "constant"},
                     {"estimator": "planted-copy", "grid": {"mode": p[:3]}}]}],
          open("suite.json", "w"))
json.dump({"name": "'><svg onload=alert(8)>", "scenes": [os.path.abspath(
               '"><img src=x onerror=alert(6)>.json')], "views": [p[3]],
           "reference": {"spp": 4, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
           "runs": [{"estimator": "raytraced", "fixed": {"rays": 1}},
                    {"estimator": "planted-copy", "grid": {"mode": p[:2]}}]},
          open("sweep.json", "w"))
PY

run() {  # run WHAT COMMAND...: fails the test, with the output, when the command fails
  local what="$1"
  shift
  if ! "$@" >"$work/out.txt" 2>&1; then
    echo "browser_injection_test: $what failed:"
    cat "$work/out.txt"
    exit 1
  fi
}
run "suite run 1" "$aoeval" run --suite suite.json --plugins plugins --out suite --db r.sqlite
run "suite run 2" "$aoeval" run --suite suite.json --plugins plugins --out suite2 --db r.sqlite
run "dashboard" "$aoeval" dashboard --db r.sqlite --out dash --no-charts
run "sweep" "$aoeval" sweep sweep.json --plugins plugins --out sweep --db s.sqlite
run "figures" "$aoeval" figures mendez-fig6 --quick --out figures

# Views "a<b" and "a>b": one estimate file each, each row naming its own.
python3 - suite/results.json <<'PY'
import json, sys
rows = json.load(open(sys.argv[1]))["rows"]
files = {}
for r in rows:
    if r["view"] in ("a<b", "a>b") and r["estimator"] == "constant":
        files[r["view"]] = r["estimate_file"]
assert len(files) == 2 and files["a<b"] != files["a>b"], files
print("views a<b and a>b: estimate files", files["a<b"], "and", files["a>b"])
PY

# The checker must catch a planted handler that reached a page raw.
cp -r suite broken
sed -i 's|</body>|<img src=x onerror=alert(99)></body>|' broken/index.html
set +e
NODE_PATH="$modules/node_modules" node "$here/check_injection.js" --marker 'alert(' \
  broken/index.html >checker.txt 2>&1
checker=$?
set -e
if [ "$checker" -ne 1 ] || ! grep -q 'planted element: <img onerror' checker.txt ||
   ! grep -q 'dialog alert(99)' checker.txt || ! grep -q 'CSP violation' checker.txt; then
  echo "browser_injection_test: the checker missed a raw planted handler (exit $checker):"
  cat checker.txt
  exit 1
fi

NODE_PATH="$modules/node_modules" node "$here/check_injection.js" --marker 'alert(' \
  suite/index.html suite/gbuffers/index.html sweep/index.html dash/index.html \
  plain:figures/index.html
