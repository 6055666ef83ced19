#!/usr/bin/env node
// Drives aoeval's image viewer (reports/viewer/viewer.js, CONTRACT §11) in Debian's headless
// chromium from file://, and fails on what a reader would see wrong:
//   - without JavaScript: an image that does not load, no leaderboard, no static mosaic;
//   - the leaderboard does not sort on a header click;
//   - element.aoevalProbe(x, y) differs by more than --tolerance (default 1e-6: a page written
//     with --viewer-exact; 1e-3 for the default compact data, reports/viewer.h) from the EXR floats
//     that exr_samples.py read with OpenImageIO (reference AO, estimate AO, their float32
//     difference, AO_stderr; a sequence's flicker and lag maps);
//   - wheel zoom, drag pan, the pixel grid, the probe readout, A/B flip (key and hover), exposure
//     and false colour do not do what they say (state and drawn pixels checked);
//   - a viewer whose static image is an error mosaic (exr_samples.py's "mosaic") disagrees with it:
//     the |error| and signed panels' colour-bar labels (the scale, nice_ceiling of the 99th
//     percentile) differ from the mosaic's bar labels as numbers, a bar's end colours differ from
//     the mosaic bar's, or, with exact data (--tolerance 1e-6 or less), a sample pixel's drawn
//     colour differs from the mosaic panel's by more than --colour-levels per channel (default 1:
//     the JavaScript interpolates the 256 generated 8-bit entries where OIIO maps the float);
//     compact float16 data moves an error by up to 4.9e-4, a few levels at a small scale;
//   - any console error, uncaught exception or failed request.
// Keeps screenshots: zoomed pixels with grid and probe, the flip, false colour, the leaderboard,
// the page without JavaScript.
//
// usage: node check_viewer.js --screenshots DIR --samples SAMPLES.json [--interact K]
//        [--tolerance T] PAGE.html
//   K: the viewer (in the samples' order) whose controls are driven; default 0; -1: none (a
//   G-buffer gallery: only the probe, the page without JavaScript and console errors are checked).
'use strict';

const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const CHROMIUM = process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium';
const problems = [];
const fail = (msg) => problems.push(msg);
let TOLERANCE = 1e-6;  // --tolerance
let COLOUR_LEVELS = 1;  // --colour-levels

function args(argv) {
  const o = { screenshots: null, samples: null, page: null, interact: 0, tolerance: 1e-6, colourLevels: 1 };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--screenshots') o.screenshots = argv[++i];
    else if (argv[i] === '--interact') o.interact = Number(argv[++i]);
    else if (argv[i] === '--tolerance') o.tolerance = Number(argv[++i]);
    else if (argv[i] === '--colour-levels') o.colourLevels = Number(argv[++i]);
    else if (argv[i] === '--samples') o.samples = argv[++i];
    else o.page = path.resolve(argv[i]);
  }
  if (!o.screenshots || !o.samples || !o.page)
    throw new Error('usage: check_viewer.js --screenshots DIR --samples SAMPLES.json PAGE.html');
  return o;
}

async function withoutJavaScript(browser, o) {
  const context = await browser.newContext({ javaScriptEnabled: false, viewport: { width: 1400, height: 900 } });
  const page = await context.newPage();
  await page.goto('file://' + o.page, { waitUntil: 'load' });
  const r = await page.evaluate(() => ({
    images: document.images.length,
    broken: Array.from(document.images).filter((i) => !i.complete || i.naturalWidth === 0).map((i) => i.src),
    leaderboard: document.querySelectorAll('table.leaderboard tbody tr').length,
    staticMosaics: document.querySelectorAll('.aoeval-viewer .av-static img.mosaic').length,
    opened: document.querySelectorAll('.av-root, .av-opener').length,
  })).catch(async () => {
    // evaluate() runs even with page JavaScript disabled (playwright's own world)
    return null;
  });
  if (!r) fail('no JavaScript: could not inspect the page');
  else {
    if (r.images === 0 || r.broken.length) fail(`no JavaScript: images did not load: ${r.broken.join(', ')}`);
    if (o.interact >= 0 && r.leaderboard === 0) fail('no JavaScript: no leaderboard rows');
    if (o.interact >= 0 && r.staticMosaics === 0) fail('no JavaScript: no static mosaic inside a viewer');
    if (r.opened !== 0) fail('no JavaScript: viewer controls appeared');
    console.log(`no JavaScript: ${r.images} images, ${r.leaderboard} leaderboard rows, ${r.staticMosaics} mosaics`);
  }
  await page.screenshot({ path: path.join(o.screenshots, `viewer-nojs-${path.basename(path.dirname(o.page))}.png`) });
  await context.close();
}

async function leaderboard(page, o) {
  const table = await page.$('table.leaderboard');
  if (!table) return fail('no leaderboard');
  const th = await table.$('th[data-sort="1"]');
  await th.click();
  const values = await table.$$eval('tbody tr', (rows) => rows.map((r) => r.cells[1].dataset.v).filter((v) => v !== ''));
  const nums = values.map(Number);
  if (nums.some((v, i) => i > 0 && v < nums[i - 1])) fail(`leaderboard not sorted ascending: ${nums}`);
  if ((await th.getAttribute('aria-sort')) !== 'ascending') fail('leaderboard header not marked ascending');
  await th.click();
  const down = (await table.$$eval('tbody tr', (rows) => rows.map((r) => r.cells[1].dataset.v).filter((v) => v !== ''))).map(Number);
  if (down.some((v, i) => i > 0 && v > down[i - 1])) fail(`leaderboard not sorted descending: ${down}`);
  await th.click();
  await table.screenshot({ path: path.join(o.screenshots, 'viewer-leaderboard.png') });
  console.log(`leaderboard: ${nums.length} rows sort both ways`);
}

async function probeMatchesExr(page, spec) {
  const byA = spec.kind === 'gbuffer' || spec.kind === 'maps';
  const el = await page.$(byA ? `.aoeval-viewer[data-a="${spec.a}"]` : `.aoeval-viewer[data-b="${spec.b}"]`);
  if (!el) return fail(`no viewer for ${spec.b || spec.a}`);
  // A sequence point's section is folded (<details>): unfold it as a reader would.
  await el.evaluate((e) => { for (let d = e.closest('details'); d; d = d.parentElement.closest('details')) d.open = true; });
  await el.scrollIntoViewIfNeeded();
  await (await el.$('.av-opener')).click();
  await page.waitForFunction((e) => typeof e.aoevalProbe === 'function', el, { timeout: 60000 });
  // A sequence's samples carry their frame (CONTRACT §11: aoevalProbe(x, y, frame)).
  const got = await el.evaluate((e, s) => s.map((p) => e.aoevalProbe(p.x, p.y, p.frame)), spec.samples);
  const worst = spec.kind === 'gbuffer' ? { Z: 0, 'N.X': 0, 'N.Y': 0, 'N.Z': 0 }
    : spec.kind === 'maps' ? { flicker: 0, lag: 0 }
      : { reference: 0, estimate: 0, error: 0, stderr: 0 };
  got.forEach((g, i) => {
    for (const k of Object.keys(worst)) {
      const d = Math.abs(g[k] - spec.samples[i][k]);
      worst[k] = Number.isNaN(d) ? Infinity : Math.max(worst[k], d);
    }
  });
  for (const k of Object.keys(worst))
    if (!(worst[k] <= TOLERANCE)) fail(`aoevalProbe ${k} differs from the EXR by ${worst[k]} (${spec.b})`);
  console.log(`probe: ${got.length} covered pixels of ${spec.a}${spec.b ? ' and ' + spec.b : ''}: max |difference| ` +
    Object.entries(worst).map(([k, v]) => `${k} ${v}`).join(', '));
  if (spec.frames) await frameSlider(el, spec);
  if (spec.mosaic) await mosaicAgrees(el, spec);
  return el;
}

// The viewer beside the mosaic it opens from (issue 46): both draw the same errors with the
// generated colour maps and scale rule (drawing/colour_maps_js.cpp), so the |error| (panel 2) and
// signed (panel 3) colour bars carry the same labels and end colours, and a pixel the same colour.
async function mosaicAgrees(el, spec) {
  const m = spec.mosaic;
  const got = await el.evaluate((e, samples) => {
    const st = e.aoevalView(), d = window.devicePixelRatio || 1;
    const canvases = e.querySelectorAll('canvas.av-canvas');
    const pixel = (i, p) => Array.from(canvases[i].getContext('2d').getImageData(
      Math.floor((st.tx + (p.x + 0.5) * st.scale) * d), Math.floor((st.ty + (p.y + 0.5) * st.scale) * d), 1, 1).data.slice(0, 3));
    return {
      ticks: Array.from(e.querySelectorAll('.av-ticks')).map((t) => Array.from(t.children).map((s) => s.textContent)),
      bars: Array.from(e.querySelectorAll('canvas.av-colourbar')).map((c) => {
        const b = c.getContext('2d').getImageData(0, 0, c.width, 1).data;
        return { low: Array.from(b.slice(0, 3)), high: Array.from(b.slice(b.length - 4, b.length - 1)) };
      }),
      abs: samples.map((p) => pixel(2, p)), signed: samples.map((p) => pixel(3, p)),
    };
  }, spec.samples);
  const num = (t) => Number(String(t).replace('\u2212', '-'));
  const off = (a, b) => Math.max(...a.map((v, c) => Math.abs(v - b[c])));
  const worst = { abs: 0, signed: 0 };
  for (const [k, i] of [['abs', 2], ['signed', 3]]) {
    const viewer = got.ticks[i].map(num), mosaic = m.labels[k].map(num);
    if (viewer.join() !== mosaic.join())
      fail(`${k} colour bar: the viewer labels it ${got.ticks[i].join(' ')}, the mosaic ${m.labels[k].join(' ')} (${spec.b})`);
    for (const end of ['low', 'high'])
      if (!(off(got.bars[i][end], m[k + '_bar'][end]) <= COLOUR_LEVELS))
        fail(`${k} colour bar: its ${end} end is ${got.bars[i][end]} in the viewer, ${m[k + '_bar'][end]} in the mosaic (${spec.b})`);
    if (!m[k] || TOLERANCE > 1e-6) continue;
    m[k].forEach((want, j) => {
      const d = off(got[k][j], want);
      worst[k] = Math.max(worst[k], d);
      if (!(d <= COLOUR_LEVELS))
        fail(`${k} panel: pixel (${spec.samples[j].x}, ${spec.samples[j].y}) is ${got[k][j]} in the viewer, ${want} in the mosaic (${spec.b})`);
    });
  }
  const pixels = m.abs && TOLERANCE <= 1e-6
    ? `; ${spec.samples.length} pixels: max |difference| abs ${worst.abs}, signed ${worst.signed} levels` : '';
  console.log(`mosaic ${m.png}: p99 ${m.p99}, scale ${m.scale}; viewer bars ${got.ticks[2].join(' ')} | ` +
    `${got.ticks[3].join(' ')}, mosaic bars ${m.labels.abs.join(' ')} | ${m.labels.signed.join(' ')}${pixels}`);
}

// A sequence's viewer: moving the frame slider to the last kept frame shows that frame (its
// number in the view state and the probe's values without a frame argument), as play does.
async function frameSlider(el, spec) {
  const last = spec.frames.length - 1, want = spec.frames[last];
  const slider = await el.$$eval('label.av-slider', (ls) => ls.findIndex((l) => l.textContent.startsWith('frame')));
  if (slider < 0) return fail(`no frame slider on the sequence viewer ${spec.b}`);
  await el.evaluate((e, a) => {
    const s = e.querySelectorAll('label.av-slider')[a.slider].querySelector('input');
    s.value = a.last; s.dispatchEvent(new Event('input'));
  }, { slider, last });
  const st = await el.evaluate((e) => e.aoevalView());
  if (st.frameNumber !== want) fail(`frame slider: the view shows frame ${st.frameNumber}, not ${want} (${spec.b})`);
  const atLast = spec.samples.filter((p) => p.frame === want);
  for (const p of atLast) {
    const g = await el.evaluate((e, q) => e.aoevalProbe(q.x, q.y), p);
    if (Math.abs(g.estimate - p.estimate) > TOLERANCE || Math.abs(g.reference - p.reference) > TOLERANCE)
      fail(`frame slider: frame ${want}'s pixel (${p.x}, ${p.y}) probes ${g.estimate}, the EXR holds ${p.estimate}`);
  }
  const shown = await el.$eval('label.av-slider output', (o) => o.textContent).catch(() => '');
  console.log(`frame slider: ${spec.frames.length} kept frames, moved to frame ${want}; ${atLast.length} probes of it match (${shown})`);
}

// Screen position of image pixel (x, y)'s centre in panel `i` of an opened viewer.
async function pixelAt(el, i, x, y) {
  const canvas = (await el.$$('canvas.av-canvas'))[i];
  await canvas.scrollIntoViewIfNeeded();
  const box = await canvas.boundingBox();
  const st = await el.evaluate((e) => e.aoevalView());
  return { x: box.x + st.tx + (x + 0.5) * st.scale, y: box.y + st.ty + (y + 0.5) * st.scale, st };
}
// The drawn colour at pixel (x, y) of panel i (the canvases hold no image file: readable).
const drawn = (el, i, x, y) => el.evaluate((e, a) => {
  const c = e.querySelectorAll('canvas.av-canvas')[a.i], st = e.aoevalView(), d = window.devicePixelRatio || 1;
  return Array.from(c.getContext('2d').getImageData(Math.floor((st.tx + (a.x + 0.5) * st.scale) * d),
    Math.floor((st.ty + (a.y + 0.5) * st.scale) * d), 1, 1).data.slice(0, 3));
}, { i, x, y });

async function interactions(page, el, spec, o) {
  const { x, y } = spec.focus || spec.samples[0];
  let p = await pixelAt(el, 1, x, y);
  await page.mouse.move(p.x, p.y);
  for (let k = 0; k < 12; ++k) await page.mouse.wheel(0, -100);  // 1.25^12 ~ 15x
  await page.waitForTimeout(100);
  const zoomed = await pixelAt(el, 1, x, y);
  if (!(zoomed.st.scale >= 8 * p.st.scale)) fail(`wheel zoom: scale ${p.st.scale} -> ${zoomed.st.scale}`);
  if (Math.abs(zoomed.x - p.x) > zoomed.st.scale || Math.abs(zoomed.y - p.y) > zoomed.st.scale)
    fail('wheel zoom did not keep the pixel under the cursor');
  await page.mouse.move(zoomed.x, zoomed.y);
  const readout = await el.$eval('.av-readout', (r) => r.textContent);
  const want = el.evaluate((e, q) => e.aoevalProbe(q.x, q.y), { x, y });
  const v = await want;
  if (!readout.includes(`pixel (${x}, ${y})`) || !readout.includes(Number(v.reference).toPrecision(6)))
    fail(`probe readout "${readout}" does not show pixel (${x}, ${y}) = ${v.reference}`);
  // Pan: a drag moves the image with the pointer.
  await page.mouse.down();
  await page.mouse.move(zoomed.x + 40, zoomed.y + 20, { steps: 4 });
  await page.mouse.up();
  const panned = await el.evaluate((e) => e.aoevalView());
  if (Math.abs(panned.tx - zoomed.st.tx - 40) > 1 || Math.abs(panned.ty - zoomed.st.ty - 20) > 1)
    fail(`drag pan: (${zoomed.st.tx}, ${zoomed.st.ty}) -> (${panned.tx}, ${panned.ty}), expected +40, +20`);
  p = await pixelAt(el, 1, x, y);
  await page.mouse.move(p.x, p.y);
  await page.waitForTimeout(100);
  if (!(panned.scale >= 6 && panned.grid)) fail('pixel grid not on at this zoom');
  await el.screenshot({ path: path.join(o.screenshots, 'viewer-zoom-grid-probe.png') });
  // A/B flip by key: the estimate panel then draws the reference's pixels.
  const ref = await drawn(el, 0, x, y);
  await page.keyboard.press('f');
  await page.waitForTimeout(100);
  const flipped = await drawn(el, 1, x, y);
  const label = await el.$eval('.av-label.av-flipped', (l) => l.textContent).catch(() => null);
  if (!(await el.evaluate((e) => e.aoevalView().flip)) || !label) fail('key f did not flip');
  if (flipped.join() !== ref.join()) fail(`flipped estimate panel shows ${flipped}, reference ${ref}`);
  await el.screenshot({ path: path.join(o.screenshots, 'viewer-flip.png') });
  await page.keyboard.press('f');
  // A/B flip by hover.
  await (await el.$('button.av-button[title^="flip"]')).hover();
  await page.waitForTimeout(100);
  if (!(await el.evaluate((e) => e.aoevalView().hoverFlip)) || (await drawn(el, 1, x, y)).join() !== ref.join())
    fail('hovering A/B did not flip');
  await page.mouse.move(p.x, p.y);
  await page.waitForTimeout(100);
  if (await el.evaluate((e) => e.aoevalView().hoverFlip)) fail('leaving A/B did not flip back');
  // Exposure, on a mid-grey pixel (neither black nor white) with the whole image in view: e twice
  // = +1 stop, and the drawn reference pixel gets brighter.
  await page.keyboard.press('0');
  const mid = spec.samples.find((q) => q.reference > 0.05 && q.reference < 0.45);
  if (!mid) fail('no reference pixel between 0.05 and 0.45 to test exposure on');
  const before = mid && await drawn(el, 0, mid.x, mid.y);
  await page.keyboard.press('e');
  await page.keyboard.press('e');
  await page.waitForTimeout(100);
  const st = await el.evaluate((e) => e.aoevalView());
  if (st.exposure !== 1) fail(`exposure after e e: ${st.exposure}`);
  if (mid) {
    const after = await drawn(el, 0, mid.x, mid.y);
    if (!(after[0] > before[0])) fail(`exposure +1 did not brighten (${mid.x}, ${mid.y}): ${before} -> ${after}`);
  }
  // False colour: the grey panel becomes coloured (R, G, B no longer equal).
  await page.keyboard.press('r');
  await page.keyboard.press('m');
  await page.waitForTimeout(100);
  const colour = mid ? await drawn(el, 0, mid.x, mid.y) : [0, 0, 0];
  if (!(await el.evaluate((e) => e.aoevalView().falseColour)) || (colour[0] === colour[1] && colour[1] === colour[2]))
    fail(`false colour: pixel ${colour}`);
  await el.screenshot({ path: path.join(o.screenshots, 'viewer-false-colour.png') });
  await page.keyboard.press('?');
  if (await el.$eval('.av-help', (h) => h.hidden)) fail('? did not show the keyboard help');
  console.log('interactions: zoom, pan, grid, probe readout, flip (key, hover), exposure, false colour, help');
}

async function main() {
  const o = args(process.argv.slice(2));
  TOLERANCE = o.tolerance;
  COLOUR_LEVELS = o.colourLevels;
  fs.mkdirSync(o.screenshots, { recursive: true });
  const samples = JSON.parse(fs.readFileSync(o.samples, 'utf8'));
  const browser = await chromium.launch({
    executablePath: CHROMIUM, headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  try {
    await withoutJavaScript(browser, o);
    const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    page.on('console', (m) => { if (m.type() === 'error') fail(`console error: ${m.text()}`); });
    page.on('pageerror', (e) => fail(`uncaught exception: ${e.message}`));
    page.on('requestfailed', (r) => fail(`request failed: ${r.url()}`));
    await page.goto('file://' + o.page, { waitUntil: 'load' });
    if (o.interact >= 0) await leaderboard(page, o);
    let driven = null;
    for (const [k, spec] of samples.entries()) {
      const el = await probeMatchesExr(page, spec);
      if (k === o.interact && el) driven = [el, spec];
    }
    if (driven) await interactions(page, driven[0], driven[1], o);
    else if (o.interact >= 0) fail(`no viewer ${o.interact} to drive`);
  } finally {
    await browser.close();
  }
  for (const p of problems) console.log(`FAIL ${p}`);
  process.exit(problems.length ? 1 : 0);
}

main().catch((e) => {
  console.error(`check_viewer.js: ${e.stack || e}`);
  process.exit(1);
});
