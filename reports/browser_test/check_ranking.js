#!/usr/bin/env node
// Does the report rank on one truth (issue 47)? Opens a suite or sweep page in Debian's headless
// chromium from file:// and reads, as a reader sees them:
//   - the leaderboard's rows in the order the page shows them (no header clicked): their true
//     scores (data-v of each row's first "true" cell) must not decrease down the table, and the
//     page must say what it ranks on;
//   - the sequences summary (when there is one): within each scene view, true steady must not
//     decrease;
//   - --expect-order A,B,C: the leaderboard's estimators, top to bottom, must be exactly these.
// Prints both orders (true and matched) so a log shows what ranking on the matched score would
// have done. Exit 1 with one line per problem.
//
// usage: node check_ranking.js [--expect-order A,B,C] [--screenshot PNG] PAGE.html
'use strict';

const path = require('path');
const { chromium } = require('playwright-core');

async function main() {
  const argv = process.argv.slice(2);
  let expect = null, shot = null, file = null;
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--expect-order') expect = argv[++i].split(',');
    else if (argv[i] === '--screenshot') shot = argv[++i];
    else file = path.resolve(argv[i]);
  }
  if (!file) throw new Error('usage: check_ranking.js [--expect-order A,B,C] [--screenshot PNG] PAGE.html');
  const browser = await chromium.launch({
    executablePath: process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  const problems = [];
  try {
    const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    const errors = [];
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto('file://' + file, { waitUntil: 'load' });
    const board = await page.evaluate(() => {
      const t = document.querySelector('table.leaderboard');
      if (!t) return null;
      return {
        says: /ranked on one truth/.test(t.previousElementSibling ? t.previousElementSibling.textContent : ''),
        rows: Array.from(t.tBodies[0].rows).map((r) => ({
          label: r.cells[0].textContent.trim(),
          true: r.cells[1].dataset.v === '' ? null : Number(r.cells[1].dataset.v),
          matched: r.cells[2].dataset.v === '' ? null : Number(r.cells[2].dataset.v),
        })),
      };
    });
    if (!board) problems.push('no leaderboard');
    else {
      if (!board.says) problems.push('the leaderboard does not say it ranks on one truth');
      const scored = board.rows.filter((r) => r.true !== null);
      scored.forEach((r, i) => {
        if (i > 0 && r.true < scored[i - 1].true)
          problems.push(`leaderboard: ${r.label} (true ${r.true}) is below ${scored[i - 1].label} (true ${scored[i - 1].true})`);
      });
      if (board.rows.findIndex((r) => r.true === null) >= 0 &&
          board.rows.slice(board.rows.findIndex((r) => r.true === null)).some((r) => r.true !== null))
        problems.push('leaderboard: a skipped row is above a scored one');
      const byMatched = scored.slice().sort((a, b) => a.matched - b.matched).map((r) => r.label);
      console.log(`leaderboard, top to bottom: ${board.rows.map((r) => `${r.label} (true ${r.true}, matched ${r.matched})`).join('; ')}`);
      console.log(`ranked on the matched score it would read: ${byMatched.join(', ')}`);
      if (expect && board.rows.map((r) => r.label).join(',') !== expect.join(','))
        problems.push(`leaderboard order ${board.rows.map((r) => r.label).join(',')}, expected ${expect.join(',')}`);
    }
    const summary = await page.evaluate(() => {
      const t = document.querySelector('table.sequences-summary');
      if (!t) return null;
      return Array.from(t.tBodies[0].rows).map((r) => ({
        label: r.cells[0].textContent.trim(), view: r.cells[1].textContent.trim(),
        true: r.cells[2].dataset.v === '' ? null : Number(r.cells[2].dataset.v),
      }));
    });
    if (summary) {
      for (let i = 1; i < summary.length; ++i) {
        const a = summary[i - 1], b = summary[i];
        if (a.view === b.view && a.true !== null && b.true !== null && b.true < a.true)
          problems.push(`sequences summary: ${b.label} (true steady ${b.true}) is below ${a.label} (${a.true}) on ${a.view}`);
      }
      console.log(`sequences summary: ${summary.length} points in order of true steady_rmse_excess per view`);
    }
    if (shot) {
      const t = await page.$('table.leaderboard');
      if (t) await t.screenshot({ path: shot });
    }
    for (const e of errors) problems.push(`console error: ${e}`);
  } finally {
    await browser.close();
  }
  for (const p of problems) console.log(`check_ranking: ${p}`);
  if (problems.length) process.exit(1);
  console.log('check_ranking: the page ranks on true rmse_excess');
}

main().catch((e) => { console.log(`check_ranking: ${e.stack || e}`); process.exit(1); });
