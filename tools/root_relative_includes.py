# Rewrites bare includes of our headers ("gbuffer.h") to root-relative paths ("scenes/gbuffer.h") (issue 27); for code written before the move. Usage: python3 tools/root_relative_includes.py .
import os, re, subprocess, sys
root = sys.argv[1]
files = subprocess.run(['git', 'ls-files', '*.cpp', '*.h'], cwd=root, capture_output=True, text=True).stdout.split()
# where each header lives (unique basenames only)
where = {}
for f in files:
    if f.endswith('.h'):
        where.setdefault(os.path.basename(f), []).append(f)
pat = re.compile(r'^(\s*#\s*include\s*")([^/"]+)(".*)$')
changed = 0
for f in files:
    p = os.path.join(root, f)
    lines = open(p).read().split('\n')
    out = []
    for l in lines:
        m = pat.match(l)
        if m and m.group(2) in where:
            cands = where[m.group(2)]
            same_dir = os.path.join(os.path.dirname(f), m.group(2))
            target = same_dir if same_dir in cands else (cands[0] if len(cands) == 1 else None)
            if target:
                l = m.group(1) + target + m.group(3)
                changed += 1
        out.append(l)
    open(p, 'w').write('\n'.join(out))
print('rewrote', changed, 'includes')
