#!/usr/bin/env node
// Measures how fast a report opens in Debian's headless chromium from file://: first paint, first
// contentful paint and the load event (ms after navigation start), the median of RUNS fresh
// browser contexts (no cache between them), and what the page read by its load event: the number
// of files and their bytes (the page itself included). A measuring tool, not a
// test (README, "The suite report"): timings depend on the machine.
//
// usage: NODE_PATH=<build>/browser_test/node_modules node measure_page.js [--runs N] PAGE.html...
'use strict';

const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');

async function main() {
  const argv = process.argv.slice(2);
  let runs = 5;
  const pages = [];
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--runs') runs = Number(argv[++i]);
    else pages.push(path.resolve(argv[i]));
  }
  if (!pages.length || !(runs > 0)) throw new Error('usage: measure_page.js [--runs N] PAGE.html...');
  const browser = await chromium.launch({
    executablePath: process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  const median = (v) => v.slice().sort((a, b) => a - b)[Math.floor(v.length / 2)];
  for (const file of pages) {
    const fp = [], fcp = [], load = [];
    let files = 0, bytes = 0;
    for (let r = 0; r < runs; ++r) {
      const context = await browser.newContext({ viewport: { width: 1400, height: 900 } });
      const page = await context.newPage();
      const read = [];
      page.on('requestfinished', (request) => read.push(request.url()));
      await page.goto('file://' + file, { waitUntil: 'load' });
      if (r === 0) {
        files = read.length;
        bytes = read.reduce((sum, url) => {
          try { return sum + fs.statSync(new URL(url)).size; } catch (e) { return sum; }
        }, 0);
      }
      // Paint entries may come after the load event (times stay relative to navigation start).
      await page.waitForFunction(() => performance.getEntriesByType('paint').length >= 2);
      const m = await page.evaluate(() => {
        const paint = {};
        for (const e of performance.getEntriesByType('paint')) paint[e.name] = e.startTime;
        const nav = performance.getEntriesByType('navigation')[0];
        return { fp: paint['first-paint'], fcp: paint['first-contentful-paint'], load: nav.loadEventStart };
      });
      fp.push(m.fp); fcp.push(m.fcp); load.push(m.load);
      await context.close();
    }
    console.log(`${file}: first paint ${median(fp).toFixed(1)} ms, first contentful paint ` +
      `${median(fcp).toFixed(1)} ms, load ${median(load).toFixed(1)} ms (median of ${runs}); ` +
      `read by load: ${files} files, ${(bytes / 1024).toFixed(0)} KiB`);
  }
  await browser.close();
}

main().catch((e) => { console.error(`measure_page.js: ${e.stack || e}`); process.exit(1); });
