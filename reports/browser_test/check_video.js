#!/usr/bin/env node
// Does each sequence video play as it should? Decodes frames of every video.png in Debian's
// headless chromium (playwright-core drives it) with the browser's own PNG decoder (APNG) through
// WebCodecs' ImageDecoder (frame by index: nothing waits for wall-clock time), draws each decoded
// frame to a canvas and compares its greys with the ones video_frames.py computed from the kept
// EXRs: the reference panel and the estimate panel (each found where it matches best in the
// frame; the estimate right of the reference) must be within MAX 8-bit grey levels (default 2) at
// every compared pixel. A frame drawn at the wrong width (rows sheared into diagonal stripes), a
// wrong palette or a missing frame fails.
//
// usage: node check_video.js [--max-diff N] VIDEO_FRAMES.json
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
  if (argv.length !== 1) throw new Error('usage: check_video.js [--max-diff N] VIDEO_FRAMES.json');
  const videos = JSON.parse(fs.readFileSync(argv[0], 'utf8'));
  const browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  let failed = 0;
  try {
    const page = await browser.newPage();
    // ImageDecoder needs a secure context: a file:// page is one (about:blank is not).
    const blank = path.join(path.dirname(path.resolve(argv[0])), 'check_video_blank.html');
    fs.writeFileSync(blank, '<!DOCTYPE html><html><body></body></html>\n');
    await page.goto('file://' + blank, { waitUntil: 'load' });
    for (const v of videos) {
      const bytes = fs.readFileSync(v.video).toString('base64');
      const indices = v.check.map((c) => c.index);
      const decoded = await page.evaluate(async ({ bytes, indices }) => {
        const data = Uint8Array.from(atob(bytes), (c) => c.charCodeAt(0));
        const decoder = new ImageDecoder({ data, type: 'image/png' });
        await decoder.tracks.ready;
        const out = { frameCount: decoder.tracks.selectedTrack.frameCount, frames: [] };
        for (const k of indices) {
          const { image } = await decoder.decode({ frameIndex: k });
          const canvas = document.createElement('canvas');
          canvas.width = image.displayWidth;
          canvas.height = image.displayHeight;
          const g = canvas.getContext('2d');
          g.drawImage(image, 0, 0);
          image.close();
          const rgba = g.getImageData(0, 0, canvas.width, canvas.height).data;
          const grey = [];
          for (let i = 0; i < rgba.length; i += 4) grey.push(rgba[i]);
          out.frames.push({ width: canvas.width, height: canvas.height, grey });
        }
        return out;
      }, { bytes, indices });
      if (decoded.frameCount !== v.frames) {
        console.log(`${v.video}: chromium decodes ${decoded.frameCount} frames, expected ${v.frames}`);
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
        console.log(`${v.video}: frame ${c.index} (sequence frame ${c.frame}) as chromium draws it, ` +
          `${f.width}x${f.height}: reference panel at (${ref.x}, ${ref.y}) max |grey diff| ` +
          `${ref.diff}, estimate panel at (${est.x}, ${est.y}) max |grey diff| ${est.diff}`);
        if (!(worst <= maxDiff)) {
          console.log(`${v.video}: frame ${c.index} differs from the kept frames by ${worst} > ${maxDiff}`);
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
