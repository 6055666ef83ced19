#!/usr/bin/env node
// Opens aoeval's HTML pages in Debian's headless chromium (playwright-core drives it; no server,
// file:// URLs) and fails on anything a reader would see broken:
//   every page:      a console error or uncaught exception, a failed request, an <img> without
//                    loading="lazy", an <img> that did not load once asked (naturalWidth == 0);
//   a dashboard:     no verdict banner, a banner other than the expected one, no history chart,
//                    a chart that did not render, hovering a new image that does not swap it for
//                    the baseline (and back);
// and keeps a full-page screenshot of each as a test artefact.
//
// usage: node check_pages.js --screenshots DIR [--hover-timeout-ms MS (30000)] KIND:PATH...
//   KIND: "page" (any report), "dashboard-pass" or "dashboard-fail" (expected verdict), optionally
//   followed by "=NAME" that the failing banner must name: dashboard-fail=hbao-split:PATH.
'use strict';

const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

const CHROMIUM = process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium';


function parseArgs(argv) {
  // ctest runs this beside other tests on every core: a hover swap may take seconds to show.
  const out = { screenshots: null, hoverTimeoutMs: 30000, pages: [] };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--screenshots') {
      out.screenshots = argv[++i];
      continue;
    }
    if (argv[i] === '--hover-timeout-ms') {
      out.hoverTimeoutMs = Number(argv[++i]);
      if (!(out.hoverTimeoutMs > 0)) throw new Error('--hover-timeout-ms: expected a positive number');
      continue;
    }
    const colon = argv[i].indexOf(':');
    if (colon < 0) throw new Error(`bad argument ${argv[i]}: expected KIND:PATH`);
    const [kind, name] = argv[i].slice(0, colon).split('=');
    if (!['page', 'dashboard-pass', 'dashboard-fail'].includes(kind))
      throw new Error(`bad kind ${kind}`);
    out.pages.push({ kind, name, file: path.resolve(argv[i].slice(colon + 1)) });
  }
  if (!out.screenshots || out.pages.length === 0)
    throw new Error('usage: check_pages.js --screenshots DIR KIND:PATH...');
  return out;
}

async function checkImages(page, problems) {
  // The pages load their images lazily (loading="lazy": only what is near the screen loads with
  // the page); the first screen's must have started with the page, the rest is asked for here,
  // and every one must then load.
  const lazy = await page.$$eval('img', (imgs) => imgs.filter((img) => img.loading !== 'lazy')
    .map((img) => img.getAttribute('src')));
  for (const src of lazy) problems.push(`image not loaded lazily: ${src}`);
  await page.$$eval('img', (imgs) => imgs.forEach((img) => { img.loading = 'eager'; }));
  await page.waitForFunction(() => Array.from(document.images).every((img) => img.complete));
  const broken = await page.$$eval('img', (imgs) =>
    imgs.filter((img) => img.naturalWidth === 0).map((img) => img.getAttribute('src')));
  for (const src of broken) problems.push(`image did not load: ${src}`);
}

async function checkDashboard(page, spec, args, problems) {
  const banner = await page.$('#verdict');
  if (!banner) {
    problems.push('no verdict banner (#verdict)');
    return;
  }
  const cls = await banner.getAttribute('class');
  const text = await banner.innerText();
  const want = spec.kind === 'dashboard-fail' ? 'fail' : 'pass';
  if (!cls.split(/\s+/).includes(want)) problems.push(`verdict banner is "${cls}", expected ${want}`);
  if (spec.name) {
    const summary = await page.$eval('table.summary', (t) => t.innerText);
    const firstRow = await page.$eval('table.summary tr:nth-child(2)', (r) => r.innerText);
    if (!firstRow.includes(spec.name) || !firstRow.includes('regressed'))
      problems.push(`first summary row does not name regressed ${spec.name}: "${firstRow}"`);
    if (!summary.includes(spec.name)) problems.push(`summary does not name ${spec.name}`);
  }
  const charts = await page.$$eval('img.chart', (imgs) =>
    imgs.map((img) => ({ src: img.getAttribute('src'), w: img.naturalWidth, h: img.naturalHeight })));
  if (charts.length === 0) problems.push('no history chart (img.chart)');
  for (const c of charts)
    if (c.w < 100 || c.h < 100) problems.push(`chart ${c.src} did not render (${c.w}x${c.h})`);

  const swaps = await page.$$('img.swap');
  if (swaps.length === 0) {
    problems.push('no hover-swap image (img.swap)');
    return;
  }
  const img = swaps[0];
  await img.scrollIntoViewIfNeeded();
  const before = await img.getAttribute('src');
  const wantNew = await img.getAttribute('data-new');
  const wantBaseline = await img.getAttribute('data-baseline');
  if (before !== wantNew) problems.push(`swap image starts at ${before}, not ${wantNew}`);
  await img.hover();
  try {
    await page.waitForFunction((el) => el.getAttribute('src') === el.dataset.baseline &&
                                       el.complete && el.naturalWidth > 0, img,
                               { timeout: args.hoverTimeoutMs });
  } catch (e) {
    problems.push(`hovering ${wantNew} did not show ${wantBaseline}`);
    return;
  }
  await page.mouse.move(0, 0);
  try {
    await page.waitForFunction((el) => el.getAttribute('src') === el.dataset.new, img,
                               { timeout: args.hoverTimeoutMs });
  } catch (e) {
    problems.push('leaving the image did not restore the new estimate');
  }
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  fs.mkdirSync(args.screenshots, { recursive: true });
  const browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--allow-file-access-from-files'],
  });
  let failed = 0;
  try {
    for (const spec of args.pages) {
      const problems = [];
      if (!fs.existsSync(spec.file)) {
        console.log(`FAIL ${spec.file}: no such file`);
        ++failed;
        continue;
      }
      const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
      page.on('console', (msg) => {
        if (msg.type() === 'error') problems.push(`console error: ${msg.text()}`);
      });
      page.on('pageerror', (err) => problems.push(`uncaught exception: ${err.message}`));
      page.on('requestfailed', (req) =>
        problems.push(`request failed: ${req.url()} (${req.failure() && req.failure().errorText})`));
      await page.goto('file://' + spec.file, { waitUntil: 'load' });
      await checkImages(page, problems);
      const count = await page.$$eval('img', (imgs) => imgs.length);
      if (spec.kind !== 'page') await checkDashboard(page, spec, args, problems);
      const shot = path.join(args.screenshots,
                             spec.kind + '-' + path.basename(path.dirname(spec.file)) + '.png');
      await page.screenshot({ path: shot, fullPage: true });
      await page.close();
      if (problems.length) {
        ++failed;
        console.log(`FAIL ${spec.file}`);
        for (const p of problems) console.log(`  ${p}`);
      } else {
        console.log(`ok   ${spec.file}: ${count} images loaded; screenshot ${shot}`);
      }
    }
  } finally {
    await browser.close();
  }
  process.exit(failed ? 1 : 0);
}

main().catch((e) => {
  console.error(`check_pages.js: ${e.stack || e}`);
  process.exit(1);
});
