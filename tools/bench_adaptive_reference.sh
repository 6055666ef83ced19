#!/bin/bash
# Rays an adaptive reference (--target-stderr) saves against uniform sampling at equal worst-pixel
# standard error (issue 16): tools/bench_adaptive_reference.sh SCENE [SAMPLER] [WxH]. Computes a
# 256-spp uniform reference, then adaptive ones starting at 32 and 64 spp whose target is the
# uniform one's worst covered pixel, and prints both worst and rms stderr and the samples spent.
set -euo pipefail
aoeval="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/build/aoeval"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
scene=${1:?scene}; smp=${2:-sobol}; res=${3:-160x120}
"$aoeval" reference --scene $scene --res $res --spp 256 --sampler $smp --no-cache -o $tmp/ad-$scene-$smp-uni.exr >/dev/null 2>&1
worst=$(/usr/bin/python3 -c "
import OpenImageIO as o, numpy as np
b=o.ImageBuf('$tmp/ad-$scene-$smp-uni.exr'); s=b.spec(); p=b.get_pixels(o.FLOAT)
n=list(s.channelnames); a=p[...,n.index('A')]>0.5; e=p[...,n.index('AO_stderr')]
print('%.6f'%e[a].max())")
for minspp in 32 64; do
"$aoeval" reference --scene $scene --res $res --spp $minspp --sampler $smp --target-stderr $worst --max-spp 16384 --no-cache -o $tmp/ad-$scene-$smp-ad$minspp.exr >/dev/null 2>&1
/usr/bin/python3 -c "
import OpenImageIO as o, numpy as np
def load(f):
  b=o.ImageBuf(f); s=b.spec(); p=b.get_pixels(o.FLOAT); n=list(s.channelnames)
  a=p[...,n.index('A')]>0.5
  spp=p[...,n.index('spp')][a] if 'spp' in n else None
  return a, p[...,n.index('AO_stderr')][a], spp
a,eu,_=load('$tmp/ad-$scene-$smp-uni.exr'); a2,ea,spp=load('$tmp/ad-$scene-$smp-ad$minspp.exr')
uni=256*a.sum(); ad=spp.sum()
print('$scene $smp $res: uniform 256 spp worst stderr %.5f rms %.5f, %d samples | adaptive (--spp $minspp --target-stderr $worst): worst %.5f rms %.5f, %d samples = %.1f%% of uniform (%.1f%% saved), max spp %d' % (eu.max(), np.sqrt((eu**2).mean()), uni, ea.max(), np.sqrt((ea**2).mean()), ad, 100*ad/uni, 100-100*ad/uni, spp.max()))
"
done
