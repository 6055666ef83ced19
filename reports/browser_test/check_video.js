#!/usr/bin/env node
// Does each sequence video play as it should? Opens the report page in Debian's headless chromium
// (playwright-core drives it), loads every video element (.aoeval-video, drawn by viewer.js on a
// canvas from the viewer's data) through element.aoevalOpen(), shows its first and last kept
// frames by index (element.aoevalVideoFrame: nothing waits for wall-clock time), reads the
// canvas's pixels and compares their greys with the ones video_frames.py computed from the kept
// EXRs: the reference panel and the estimate panel (each found where it matches best in the
// frame; the estimate right of the reference) must be within MAX 8-bit grey levels (default 2) at
// every compared pixel. A missing video, a wrong frame or a missing frame fails.
//
// usage: node check_video.js [--max-diff N] VIDEO_FRAMES.json PAGE.html
'use strict';

const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const CHROMIUM = process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium';

// The best placement of a w x h panel (greys `want`, compared where `mask`) in the frame's greys:
// the offset with the least largest difference, searched at x >= fromX.
function place(frame, W, H, want, mask, w, h, fromX) {
  let best = { diff: 256, x: -1, y: -1 };
  for (let y0 = 0; y0 + h <= H; ++y0) {
    for (let x0 = fromX; x0 + w <= W; ++x0) {
      let worst = 0;
      for (let y = 0; y < h && worst < best.diff; ++y) {
        for (let x = 0; x < w; ++x) {
          const k = y * w + x;
          if (!mask[k]) continue;
          const d = Math.abs(frame[(y0 + y) * W + x0 + x] - want[k]);
          if (d > worst) {
            worst = d;
            if (worst >= best.diff) break;
          }
        }
      }
      if (worst < best.diff) best = { diff: worst, x: x0, y: y0 };
    }
  }
  return best;
}

async function main() {
  const argv = process.argv.slice(2);
  let maxDiff = 2;
  if (argv[0] === '--max-diff') {
    maxDiff = Number(argv[1]);
    argv.splice(0, 2);
  }
  if (argv.length !== 2) throw new Error('usage: check_video.js [--max-diff N] VIDEO_FRAMES.json PAGE.html');
  const videos = JSON.parse(fs.readFileSync(argv[0], 'utf8'));
  const browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  let failed = 0;
  try {
    const page = await browser.newPage();
    page.on('pageerror', (e) => { console.log(`page error: ${e.message}`); ++failed; });
    await page.goto('file://' + path.resolve(argv[1]), { waitUntil: 'load' });
    for (const v of videos) {
      const indices = v.check.map((c) => c.index);
      const decoded = await page.evaluate(async ({ manifest, indices }) => {
        const el = [...document.querySelectorAll('.aoeval-video')].find((e) => e.dataset.manifest === manifest);
        if (!el) return { missing: true };
        await el.aoevalOpen();
        const canvas = el.querySelector('canvas');
        const out = { frameCount: el.aoevalVideoFrameCount, frames: [] };
        for (const k of indices) {
          const shown = el.aoevalVideoFrame(k);
          const rgba = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
          const grey = [];
          for (let i = 0; i < rgba.length; i += 4) grey.push(rgba[i]);
          out.frames.push({ width: canvas.width, height: canvas.height, frame: shown.frame, grey });
        }
        return out;
      }, { manifest: v.manifest, indices });
      if (decoded.missing) {
        console.log(`${v.manifest}: the page has no video of it`);
        ++failed;
        continue;
      }
      if (decoded.frameCount !== v.frames) {
        console.log(`${v.manifest}: the video holds ${decoded.frameCount} frames, expected ${v.frames}`);
        ++failed;
      }
      v.check.forEach((c, i) => {
        const f = decoded.frames[i];
        const mask = Buffer.from(c.mask, 'base64');
        const ref = place(f.grey, f.width, f.height, Buffer.from(c.reference, 'base64'), mask,
          c.width, c.height, 0);
        const est = place(f.grey, f.width, f.height, Buffer.from(c.estimate, 'base64'), mask,
          c.width, c.height, ref.x + c.width);
        const worst = Math.max(ref.diff, est.diff);
        console.log(`${v.manifest}: frame ${c.index} (sequence frame ${c.frame}; shown: ${f.frame}) as chromium draws it, ` +
          `${f.width}x${f.height}: reference panel at (${ref.x}, ${ref.y}) max |grey diff| ` +
          `${ref.diff}, estimate panel at (${est.x}, ${est.y}) max |grey diff| ${est.diff}`);
        if (!(worst <= maxDiff) || f.frame !== c.frame) {
          console.log(`${v.manifest}: frame ${c.index} differs from the kept frames by ${worst} > ${maxDiff}`);
          ++failed;
        }
      });
    }
  } finally {
    await browser.close();
  }
  if (failed) {
    console.log(`check_video: ${failed} problem(s)`);
    process.exit(1);
  }
  console.log(`check_video: ${videos.length} video(s) play their kept frames within ${maxDiff} grey levels`);
}

main().catch((e) => {
  console.error(e.stack || String(e));
  process.exit(2);
});
