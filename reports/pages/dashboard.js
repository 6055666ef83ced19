// The dashboard (reports/dashboard_html.cpp): hovering a new image shows its baseline in its place
// (the browser test checks the swap). A file beside the page: its Content-Security-Policy allows
// no inline script.
document.querySelectorAll('img.swap').forEach(function (img) {
  img.addEventListener('mouseenter', function () { img.src = img.dataset.baseline; });
  img.addEventListener('mouseleave', function () { img.src = img.dataset.new; });
});
