// Sortable tables of aoeval's pages (the leaderboard): a click on a header with data-sort sorts the
// rows below the header rows by that column, ascending, then descending. A cell's data-v holds the
// number to sort by; a cell without one (skipped, blank) sorts last either way. No library.
'use strict';
(function () {
  function sortBy(table, th) {
    const col = Number(th.dataset.sort), body = table.tBodies[0];
    const up = th.getAttribute('aria-sort') !== 'ascending';
    table.querySelectorAll('th[data-sort]').forEach(function (h) { h.removeAttribute('aria-sort'); });
    th.setAttribute('aria-sort', up ? 'ascending' : 'descending');
    const key = function (tr) {
      const td = tr.cells[col];
      if (!td) return null;
      if (th.dataset.type === 'text') return td.textContent.trim();
      return td.dataset.v === undefined || td.dataset.v === '' ? null : Number(td.dataset.v);
    };
    const rows = Array.from(body.rows);
    rows.sort(function (a, b) {
      const x = key(a), y = key(b);
      if (x === null || y === null) return (x === null) - (y === null);  // blanks last
      const c = typeof x === 'string' ? x.localeCompare(y) : x - y;
      return up ? c : -c;
    });
    rows.forEach(function (tr) { body.appendChild(tr); });
  }
  function init() {
    document.querySelectorAll('table.sortable').forEach(function (table) {
      table.querySelectorAll('th[data-sort]').forEach(function (th) {
        th.title = 'sort by this column';
        th.addEventListener('click', function () { sortBy(table, th); });
      });
    });
  }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', init);
  else init();
})();
