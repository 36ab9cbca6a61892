// Injected at the top of a copy of a dampid HTML report by check.sh (the report itself
// has no scripts). Records console errors and uncaught errors from the start, and on
// load measures the page as laid out and writes the result as JSON into
// <pre id="dampid-check">, which chromium --dump-dom prints.
(function () {
  var errors = [];
  var original = console.error;
  console.error = function () {
    errors.push(Array.prototype.map.call(arguments, String).join(' '));
    return original.apply(console, arguments);
  };
  window.addEventListener('error', function (e) {
    errors.push(String(e.message || e.type) + ' ' + (e.filename || (e.target && (e.target.src || e.target.href)) || ''));
  }, true);
  window.addEventListener('load', function () {
    var result = { errors: errors, overflow: [], smallText: [], plots: 0, withoutLegend: [], minText: Infinity };
    var width = document.documentElement.clientWidth;
    result.viewport = width;
    result.height = document.documentElement.scrollHeight;
    result.scrollWidth = document.documentElement.scrollWidth;
    // No element may stick out of the viewport (a scrolling table keeps its box inside).
    document.querySelectorAll('body *').forEach(function (el) {
      var r = el.getBoundingClientRect();
      if (r.width > 0 && r.right > width + 1) {
        result.overflow.push(el.tagName + ' right=' + Math.round(r.right));
      }
    });
    document.querySelectorAll('svg').forEach(function (svg, k) {
      result.plots += 1;
      var box = svg.viewBox && svg.viewBox.baseVal;
      var scale = box && box.width ? svg.getBoundingClientRect().width / box.width : 1;
      var texts = svg.querySelectorAll('text');
      texts.forEach(function (t) {
        if (!t.textContent.trim()) return;
        var shown = parseFloat(getComputedStyle(t).fontSize) * scale;
        result.minText = Math.min(result.minText, shown);
        if (shown < 12) result.smallText.push('plot ' + k + ': "' + t.textContent.trim() + '" ' + shown.toFixed(1) + ' px');
      });
      // plotters draws a legend as a translucent white box with the series names in it.
      var legend = Array.prototype.some.call(svg.querySelectorAll('rect'), function (rect) {
        if (rect.getAttribute('opacity') !== '0.85' || rect.getAttribute('fill') !== '#FFFFFF') return false;
        var r = rect.getBoundingClientRect();
        return Array.prototype.some.call(texts, function (t) {
          var q = t.getBoundingClientRect();
          return t.textContent.trim() && q.left >= r.left - 1 && q.right <= r.right + 1 && q.top >= r.top - 1 && q.bottom <= r.bottom + 1;
        });
      });
      if (!legend) result.withoutLegend.push(k);
    });
    result.notDetermined = document.body.innerText.indexOf('not determined') >= 0;
    var pre = document.createElement('pre');
    pre.id = 'dampid-check';
    pre.textContent = JSON.stringify(result);
    document.body.appendChild(pre);
  });
})();
