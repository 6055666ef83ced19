#!/usr/bin/env node
// Opens pages whose every user-controlled string was planted with script (run_injection_test.sh)
// in Debian's headless chromium and fails on any sign that one became markup (issue 48):
//   - any alert/confirm/prompt dialog, with the page's Content-Security-Policy bypassed (so that
//     escaping alone is tested: a planted handler would run) and with it in force;
//   - any console message of a CSP violation with the policy in force (a planted inline handler
//     or script the policy had to stop; the pages' own scripts cause none);
//   - any element with an inline event handler attribute (on*), any <script> other than the
//     pages' own files (viewer/*.js, dashboard.js, viewer-data/*.js), any <img> whose src is the
//     planted "x", any <svg> or <iframe>;
//   - a page on which no planted string shows as text (the plant did not reach it: the check
//     would prove nothing), or that throws or logs a console error of its own.
// Viewers are opened (element.aoevalOpen) so that what they build is checked too.
//
// usage: node check_injection.js --marker TEXT [plain:]PAGE...
//   plain: a page that shows no user string (the figures index): the same checks but the marker.
// prints one line per page: "<page>: alerts 0, csp violations 0, planted elements 0, planted
// strings shown as text N"; exit 1 on any problem.
'use strict';

const path = require('path');
const { chromium } = require('playwright-core');

const CHROMIUM = process.env.AOEVAL_CHROMIUM || '/usr/bin/chromium';

async function visit(browser, file, bypassCSP, marker) {
  const context = await browser.newContext({ bypassCSP });
  const page = await context.newPage();
  const seen = { alerts: [], csp: [], errors: [] };
  page.on('dialog', async (d) => {
    seen.alerts.push(`${d.type()}(${d.message()})`);
    await d.dismiss();
  });
  page.on('console', (m) => {
    const t = m.text();
    if (/Content Security Policy/i.test(t)) seen.csp.push(t);
    else if (m.type() === 'error' && !/Failed to load resource/.test(t)) seen.errors.push(t);
  });
  page.on('pageerror', (e) => seen.errors.push(String(e)));
  await page.goto('file://' + file, { waitUntil: 'load' });
  // Every image loads now (a planted onerror would fire), every viewer opens.
  await page.$$eval('img', (imgs) => imgs.forEach((img) => { img.loading = 'eager'; }));
  await page.waitForFunction(() => Array.from(document.images).every((img) => img.complete));
  await page.evaluate(async () => {
    for (const v of document.querySelectorAll('.aoeval-viewer'))
      if (typeof v.aoevalOpen === 'function') await v.aoevalOpen();
  });
  await page.waitForTimeout(200);  // a handler queued by the last image or viewer runs now
  const found = await page.evaluate((markerText) => {
    const bad = [];
    for (const el of document.querySelectorAll('*')) {
      for (const a of el.attributes)
        if (/^on/i.test(a.name)) bad.push(`<${el.tagName.toLowerCase()} ${a.name}="${a.value}">`);
    }
    for (const s of document.querySelectorAll('script')) {
      const src = s.getAttribute('src') || '';
      if (!/^(viewer\/(viewer|report|colour_maps)\.js|dashboard\.js|viewer-data\/[A-Za-z0-9._-]+\.js)$/.test(src))
        bad.push(`<script src="${src}">${s.textContent.slice(0, 60)}`);
    }
    for (const img of document.querySelectorAll('img'))
      if (img.getAttribute('src') === 'x') bad.push('<img src="x">');
    for (const el of document.querySelectorAll('svg, iframe, object, embed'))
      bad.push(`<${el.tagName.toLowerCase()}>`);
    const textCount = document.body.innerText.split(markerText).length - 1;
    return { bad, textCount };
  }, marker);
  await context.close();
  return { ...seen, ...found };
}

async function main() {
  const argv = process.argv.slice(2);
  let marker = null;
  const pages = [];
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--marker') marker = argv[++i];
    else if (argv[i].startsWith('plain:')) pages.push({ file: path.resolve(argv[i].slice(6)), plain: true });
    else pages.push({ file: path.resolve(argv[i]), plain: false });
  }
  if (!marker || pages.length === 0) throw new Error('usage: check_injection.js --marker TEXT PAGE...');
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: ['--no-sandbox'] });
  let failed = false;
  for (const { file, plain } of pages) {
    const problems = [];
    const open = await visit(browser, file, true, marker);    // escaping alone
    const guarded = await visit(browser, file, false, marker);  // escaping and the policy
    const alerts = open.alerts.length + guarded.alerts.length;
    for (const a of open.alerts.concat(guarded.alerts)) problems.push(`dialog ${a}`);
    for (const c of guarded.csp) problems.push(`CSP violation: ${c}`);
    for (const b of open.bad) problems.push(`planted element: ${b}`);
    for (const e of guarded.errors) problems.push(`console error: ${e}`);
    if (!plain && open.textCount === 0) problems.push(`no planted string ("${marker}") shows as text`);
    console.log(`${path.relative(process.cwd(), file)}: alerts ${alerts}, csp violations ` +
                `${guarded.csp.length}, planted elements ${open.bad.length}, planted strings ` +
                `shown as text ${open.textCount}`);
    for (const p of problems) console.log(`  FAIL ${p}`);
    failed = failed || problems.length > 0;
  }
  await browser.close();
  process.exit(failed ? 1 : 0);
}

main().catch((e) => {
  console.error(e);
  process.exit(2);
});
