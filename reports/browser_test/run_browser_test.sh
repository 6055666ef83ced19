#!/usr/bin/env bash
# ctest "browser_test" (reports/CMakeLists.txt): builds a tiny suite report and two dashboards in a
# temporary folder with the aoeval binary, then opens them in Debian's headless chromium
# (check_pages.js, playwright-core) and fails on console errors, images that do not load, charts
# that did not render, a hover swap that does not swap, or a verdict other than expected; and first
# shows that the checker catches a deliberately broken copy of a dashboard. Then drives the image
# viewer of the suite report (check_viewer.js): element.aoevalProbe against the EXR floats that
# exr_samples.py reads with OpenImageIO at 100 random covered pixels per viewer, zoom, pan, flip,
# probe, exposure, false colour, the sortable leaderboard, and the page without JavaScript; and
# that a sweep mixing estimators of different AO definitions ranks on true AO (check_ranking.js).
# Screenshots are kept in <build>/test-artifacts/.
#
#   run_browser_test.sh AOEVAL BUILD_DIR
#
# playwright-core is pinned by package-lock.json and installed with `npm ci` into
# <build>/browser_test/node_modules (never into the source tree), again only when the lock changes.
# Exit 77 (ctest: skipped) when chromium or node is absent (./test.sh installs both) or when npm
# cannot install playwright-core.
set -euo pipefail
aoeval="$(realpath "$1")"
build="$(realpath "$2")"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
chromium="${AOEVAL_CHROMIUM:-/usr/bin/chromium}"

# chromium, node and playwright-core (exit 77 without them): playwright_modules.sh.
# shellcheck source=playwright_modules.sh
source "$here/playwright_modules.sh"
modules="$(playwright_modules "$here" "$build" "$chromium")" || exit $?

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export AOEVAL_CACHE="$work/cache"  # its own reference cache
cd "$work"
cat >tiny.json <<'JSON'
[{"name": "tiny", "scenes": ["cornell-box"], "res": [64, 48],
  "reference": {"spp": 16, "sampler": "sobol"},
  "timing": {"warmup": 1, "repetitions": 5},
  "runs": [{"estimator": "constant"}, {"estimator": "raytraced", "fixed": {"rays": 8}}]}]
JSON
# Timing is not what this test checks (a shared CI machine); accuracy rules decide the verdicts.
echo '{"defaults": {"time_relative": 1000}}' >accuracy_only.json

expect_status() {  # expect_status CODE COMMAND...
  local want="$1"
  shift
  set +e
  "$@" >"$work/out.txt" 2>&1
  local got=$?
  set -e
  if [ "$got" -ne "$want" ]; then
    echo "browser_test: '$*' exited $got, expected $want:"
    cat "$work/out.txt"
    exit 1
  fi
}

# expect_checker_fails WHAT MESSAGE CHECKER ARGS...: the checker script CHECKER (run by node with
# ARGS) must fail (exit 1) on a planted broken page, saying MESSAGE; WHAT names the plant.
expect_checker_fails() {
  local what="$1" message="$2" checker="$3" status
  shift 3
  set +e
  NODE_PATH="$modules/node_modules" node "$here/$checker" "$@" >checker-output.txt 2>&1
  status=$?
  set -e
  if [ "$status" -ne 1 ] || ! grep -q "$message" checker-output.txt; then
    echo "browser_test: $checker missed \"$message\" in $what (exit $status):"
    cat checker-output.txt
    exit 1
  fi
  echo "browser_test: $checker catches $what: $(grep -m 1 "$message" checker-output.txt)"
}

# expect_viewer_check_fails PAGE SAMPLES TOLERANCE MESSAGE: check_viewer.js must fail on the broken
# copy PAGE of a page, saying MESSAGE.
expect_viewer_check_fails() {
  expect_checker_fails "$1" "$4" check_viewer.js --screenshots "$work/shots" --tolerance "$3" \
    --interact -1 --samples "$2" "$1/index.html"
}

expect_status 0 "$aoeval" run --suite tiny.json --out suite-a --db r.sqlite
# raytraced made worse (1 ray instead of 8): the dashboard fails and names it.
expect_status 0 "$aoeval" run --suite tiny.json --out suite-b --db r.sqlite --set raytraced:rays=1
expect_status 1 "$aoeval" dashboard --db r.sqlite --out dash-fail --config accuracy_only.json
# CONTRACT §12: the line names the row's parameters, the ones that differ from the defaults first.
grep -Eq "REGRESSED raytraced rays=1(,[^ ]*)? scene cornell-box" "$work/out.txt" || { cat "$work/out.txt"; exit 1; }
# Back to 8 rays: an improvement, no regression.
expect_status 0 "$aoeval" run --suite tiny.json --out suite-c --db r.sqlite
# The same run's page with the viewer's exact float32 data (--viewer-exact; issue 42).
expect_status 0 "$aoeval" run --suite tiny.json --out suite-x --db x.sqlite --viewer-exact
expect_status 0 "$aoeval" dashboard --db r.sqlite --out dash-pass --config accuracy_only.json

# The checker itself must catch a broken page: a missing image, a console error, no hover swap.
cp -r dash-fail broken
rm "$(find broken/images -name baseline.png | head -n 1)"
sed -i -e 's|img.addEventListener|void|g' broken/dashboard.js
# (A script file beside the page: the page's Content-Security-Policy refuses inline script.)
echo 'console.error("planted");' >broken/planted.js
sed -i -e 's|</body>|<script src="planted.js"></script></body>|' broken/index.html
set +e
# (The hover is expected to time out here, so a short wait will do.)
NODE_PATH="$modules/node_modules" node "$here/check_pages.js" --screenshots "$work/shots" \
  --hover-timeout-ms 5000 dashboard-fail:broken/index.html >checker.txt 2>&1
checker=$?
set -e
for expected in "image did not load" "console error: planted" "did not show"; do
  if [ "$checker" -ne 1 ] || ! grep -q "$expected" checker.txt; then
    echo "browser_test: the checker missed \"$expected\" on a broken page (exit $checker):"
    cat checker.txt
    exit 1
  fi
done

NODE_PATH="$modules/node_modules" node "$here/check_pages.js" \
  --screenshots "$build/test-artifacts" \
  page:suite-b/index.html \
  dashboard-fail=raytraced:dash-fail/index.html \
  dashboard-pass:dash-pass/index.html

# The viewer (CONTRACT §11). Debian's python3 has python3-openimageio (./test.sh installs it).
# The default page's data is compact (float16 where that holds every value within 1e-3, deflated;
# reports/viewer.h): its probe must agree with the EXRs within 1e-3. The --viewer-exact page's
# must agree exactly (1e-6).
/usr/bin/python3 "$here/exr_samples.py" suite-b/index.html 100 samples.json
/usr/bin/python3 "$here/exr_samples.py" suite-x/index.html 100 samples-x.json
# First, the probe check must catch viewer data off the EXR (every estimate AO float nudged):
# 1e-5 off in the exact data, 3e-3 off in the compact data (re-encoded as the writer does).
cp -r suite-x viewer-broken
/usr/bin/python3 - viewer-broken/viewer-data/runs__*__estimates__raytraced*.js <<'PY'
import base64, json, sys
import numpy as np
path = sys.argv[1]
text = open(path).read()
head, record = text[:text.index("]=") + 2], json.loads(text[text.index("]=") + 2:].rstrip().rstrip(";"))
ao = np.frombuffer(base64.b64decode(record["channels"]["AO"][0]), "<f4") + np.float32(1e-5)
record["channels"]["AO"][0] = base64.b64encode(ao.astype("<f4").tobytes()).decode()
open(path, "w").write(head + json.dumps(record) + ";\n")
PY
cp -r suite-b viewer-broken-compact
/usr/bin/python3 - viewer-broken-compact/viewer-data/runs__*__estimates__raytraced*.js <<'PY'
import json, re, sys, zlib
import numpy as np
# The compact script (reports/viewer.h): line 2 the record, line 3 the byte string (js_byte_string)
# whose [offset, length] parts are the deflated planes.
path = sys.argv[1]
text = open(path, encoding="latin-1").read()
head, line2, line3 = text.split("\n", 2)
key_end = line2.index("]=") + 2
record = json.loads(line2[key_end:].rstrip(";"))
start = line3.index('.bin="') + 6
bin = re.sub(r'\\(.)', lambda m: {"n": "\n", "r": "\r"}.get(m.group(1), m.group(1)),
             line3[start:line3.rindex('";')]).encode("latin-1")
assert record["encoding"] == "shuffled-deflate" and record["kinds"]["AO"][0] == "h"
off, size = record["channels"]["AO"][0]
u = np.frombuffer(zlib.decompress(bin[off:off + size]), np.uint8)
n = u.size // 2
ao = u.reshape(2, n).T.copy().view("<f2").ravel().astype(np.float32) + np.float32(3e-3)
z = zlib.compress(ao.astype("<f2").view(np.uint8).reshape(n, 2).T.copy().tobytes())
record["channels"]["AO"][0] = [len(bin), len(z)]
bin += z
escaped = bin.decode("latin-1").replace("\\", "\\\\").replace('"', '\\"')
escaped = escaped.replace("\n", "\\n").replace("\r", "\\r")
open(path, "w", encoding="latin-1").write(head + "\n" + line2[:key_end] + json.dumps(record) + ";\n" +
                                          line3[:start] + escaped + '";\n')
PY
expect_viewer_check_fails viewer-broken samples-x.json 1e-6 "aoevalProbe estimate differs"
expect_viewer_check_fails viewer-broken-compact samples.json 1e-3 "aoevalProbe estimate differs"
# The viewer beside its mosaic (issue 46): the check must catch a viewer whose scale rule or colour
# map left the C++ one: nice_ceiling of twice the p99 (the bars' labels), and the map 2 levels
# redder (the colours of the bars and of the exact page's pixels).
cp -r suite-x mosaic-broken-scale
sed -i -e 's|x = Math.fround(x);|x = Math.fround(2 * x);|' mosaic-broken-scale/viewer/colour_maps.js
cp -r suite-x mosaic-broken-colour
sed -i -e 's|return \[a\[0\] + f|return [2 + a[0] + f|' mosaic-broken-colour/viewer/viewer.js
expect_viewer_check_fails mosaic-broken-scale samples-x.json 1e-6 "colour bar: the viewer labels it"
expect_viewer_check_fails mosaic-broken-colour samples-x.json 1e-6 "panel: pixel"
NODE_PATH="$modules/node_modules" node "$here/check_viewer.js" --tolerance 1e-3 \
  --screenshots "$build/test-artifacts" --samples samples.json suite-b/index.html
NODE_PATH="$modules/node_modules" node "$here/check_viewer.js" --tolerance 1e-6 --interact -1 \
  --screenshots "$work/shots" --samples samples-x.json suite-x/index.html
# A sequence sweep's page (CONTRACT §10-11): its viewers hold every kept frame; aoevalProbe(x, y,
# frame) equals each frame's EXR floats, and the frame slider shows the frame it is moved to.
cat >slide.json <<'JSON'
{"objects": [{"name": "floor", "generator": "plane", "params": {"size": [4, 4]}},
             {"name": "box", "generator": "box", "params": {"size": [0.5, 0.5, 0.5]}}],
 "views": [{"name": "slide", "eye": [0, 1.2, 1.6], "target": [0, 0.2, 0], "fov_y_deg": 50,
            "width": 48, "height": 36,
            "sequence": {"frames": 6, "fps": 10,
              "camera": [{"frame": 5, "eye": [0.4, 1.2, 1.6], "target": [0.1, 0.2, 0]}],
              "objects": {"box": [{"frame": 0, "translate": [-0.4, 0, 0]},
                                  {"frame": 5, "translate": [0.4, 0, 0]}]}}}]}
JSON
cat >seq.json <<JSON
{"name": "seq", "scenes": ["$work/slide.json"], "views": ["slide"],
 "reference": {"spp": 16, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
 "runs": [{"estimator": "raytraced", "fixed": {"rays": 2}}]}
JSON
expect_status 0 "$aoeval" sweep seq.json --out seq --db seq.sqlite
grep -q '<section class="sequence" ' seq/index.html || { echo "browser_test: no sequence section"; exit 1; }
/usr/bin/python3 "$here/exr_samples.py" seq/index.html 60 seq-samples.json
grep -q '"frames"' seq-samples.json || { echo "browser_test: the sequence page has no multi-frame viewer"; exit 1; }
NODE_PATH="$modules/node_modules" node "$here/check_viewer.js" --interact -1 --tolerance 1e-3 \
  --screenshots "$build/test-artifacts" --samples seq-samples.json seq/index.html
# One truth to rank on (issue 47): a sweep mixing a bounded estimator (hbao-split-cpu, dmax 0.3
# linear: near its own reference, far from true AO), rtao and raytraced over the moving scene; the
# leaderboard and the sequences summary, as chromium shows them, are in the order of true
# steady_rmse_excess. First, the checker must catch a leaderboard whose rows are reversed.
cat >mix.json <<JSON
{"name": "mix", "scenes": ["$work/slide.json"], "views": ["slide"],
 "reference": {"spp": 16, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
 "runs": [{"estimator": "hbao-split-cpu"}, {"estimator": "rtao"},
          {"estimator": "raytraced", "fixed": {"rays": 4}}]}
JSON
expect_status 0 "$aoeval" sweep mix.json --out mix --db mix.sqlite
cp -r mix ranking-broken
/usr/bin/python3 - ranking-broken/index.html <<'PY'
import re, sys
path = sys.argv[1]
html = open(path).read()
start = html.index("<tbody>", html.index('class="leaderboard')) + len("<tbody>")
end = html.index("</tbody>", start)
rows = re.findall(r"<tr>.*?</tr>\n", html[start:end], re.S)
assert len(rows) >= 2, rows
open(path, "w").write(html[:start] + "\n" + "".join(reversed(rows)) + html[end:])
PY
expect_checker_fails "a reversed leaderboard" "is below" check_ranking.js ranking-broken/index.html
NODE_PATH="$modules/node_modules" node "$here/check_ranking.js" \
  --screenshot "$build/test-artifacts/ranking-leaderboard.png" mix/index.html
# The G-buffer gallery's viewers: Z and N under the probe equal the EXR's.
/usr/bin/python3 "$here/exr_samples.py" suite-b/gbuffers/index.html 100 gbuffer-samples.json
NODE_PATH="$modules/node_modules" node "$here/check_viewer.js" --interact -1 --tolerance 1e-3 \
  --screenshots "$build/test-artifacts" --samples gbuffer-samples.json suite-b/gbuffers/index.html
# The sequence video plays what it holds (CONTRACT §10): the page's video (viewer.js, drawn on a
# canvas from the viewer's data) shows its first and last frames (by index: no waiting on time)
# and the reference and estimate panels equal the kept EXRs' 8-bit greys within 2 levels (the
# data's float16 AO moves a grey by at most 1.6 levels). Twelve frames. First, the checker must
# catch a video that shows frame 0 whatever frame it is asked for.
sed -e 's/"frames": 6/"frames": 12/' -e 's/"frame": 5/"frame": 11/g' slide.json >slide12.json
cat >video.json <<JSON
{"name": "video", "scenes": ["$work/slide12.json"], "views": ["slide"], "res": [40, 30],
 "reference": {"spp": 8, "sampler": "sobol"}, "timing": {"warmup": 0, "repetitions": 1},
 "runs": [{"estimator": "raytraced", "fixed": {"rays": 2}}]}
JSON
expect_status 0 "$aoeval" sweep video.json --out video --db video.sqlite
/usr/bin/python3 "$here/video_frames.py" video video-frames.json
cp -r video video-broken
sed -i -e 's|const shown = i,|const shown = 0,|' video-broken/viewer/viewer.js
expect_checker_fails "a video stuck on frame 0" "differs from the kept frames" check_video.js \
  video-frames.json video-broken/index.html
NODE_PATH="$modules/node_modules" node "$here/check_video.js" video-frames.json video/index.html
