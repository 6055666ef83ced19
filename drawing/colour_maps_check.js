// ctest colour_maps_js_test: the generated colour_maps.js (drawing/colour_maps_js.cpp) loaded as
// the pages load it; its JavaScript scale rule must give the answers the C++ gave (`checks`), and
// its tables must be 256 sRGB byte triples. `node colour_maps_check.js colour_maps.js`.
'use strict';
const fs = require('fs');
const vm = require('vm');
const context = {};
vm.runInNewContext(fs.readFileSync(process.argv[2], 'utf8') + '\nthis.maps = AOEVAL_COLOUR_MAPS;',
  context);
const maps = context.maps;
const failures = [];
for (const [x, want] of maps.checks.niceCeiling) {
  const got = maps.niceCeiling(x);
  if (got !== Math.fround(want)) failures.push('niceCeiling(' + x + ') = ' + got + ', C++ ' + want);
}
for (const [n, want] of maps.checks.p99Rank) {
  const got = maps.p99Rank(n);
  if (got !== want) failures.push('p99Rank(' + n + ') = ' + got + ', C++ ' + want);
}
for (const name of ['inferno', 'rdbu']) {
  const t = maps[name];
  if (t.length !== 256) failures.push(name + ': ' + t.length + ' entries, not 256');
  for (const c of t)
    if (c.length !== 3 || c.some(function (v) { return !(v >= 0 && v <= 255 && v === (v | 0)); }))
      failures.push(name + ': not an sRGB byte triple: ' + JSON.stringify(c));
}
// autoScale over a known set: 1..200 / 1000 -> the 198th smallest (rank ceil(198) - 1 = 197), 0.198,
// whose nice ceiling is 0.2.
const v = [];
for (let i = 1; i <= 200; ++i) v.push(-i / 1000);
if (maps.autoScale(v) !== Math.fround(0.2)) failures.push('autoScale(1..200 / 1000) = ' + maps.autoScale(v));
if (failures.length) {
  console.error(failures.join('\n'));
  process.exit(1);
}
console.log('colour maps: ' + maps.checks.niceCeiling.length + ' nice_ceiling and ' +
  maps.checks.p99Rank.length + ' p99_rank answers of the C++ reproduced');
