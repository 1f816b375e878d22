// The report's only script: sorting and filtering of the route table, then self-checks that
// write #status and document.title. A URL fragment `#test:sort=COL:asc|desc;filter=TEXT;state=S`
// drives the same functions and records the resulting order in #test-result (the browser test);
// `open=ID` opens a route's drill-down, whose event markers are then measured back to frames.
(function () {
  "use strict";
  // Other pages (sds compare): every table.sortable sorts on a click on its heading (numbers by
  // data-v, empty cells last); `#test:sort=COL:asc|desc` sorts #per-route and lists its keys.
  function sortables() {
    Array.prototype.forEach.call(document.querySelectorAll("table.sortable"), function (t) {
      var hs = t.tHead.rows[0].cells, tb = t.tBodies[0], rs = Array.prototype.slice.call(tb.rows);
      function by(col, dir) {
        var sign = dir === "descending" ? -1 : 1;
        function k(r) { var v = r.cells[col].getAttribute("data-v"); return v === null ? r.cells[col].textContent : (v === "" ? NaN : parseFloat(v)); }
        rs.slice().sort(function (a, b) {
          var x = k(a), y = k(b), xn = typeof x === "number", yn = typeof y === "number";
          if (xn && isNaN(x)) { return isNaN(y) ? 0 : 1; }
          if (yn && isNaN(y)) { return -1; }
          var r = xn && yn ? x - y : String(x).localeCompare(String(y));
          return r === 0 ? (+a.getAttribute("data-i")) - (+b.getAttribute("data-i")) : sign * r;
        }).forEach(function (r) { tb.appendChild(r); });
        for (var i = 0; i < hs.length; i++) { hs[i].removeAttribute("aria-sort"); }
        hs[col].setAttribute("aria-sort", dir);
      }
      Array.prototype.forEach.call(hs, function (h, i) {
        h.addEventListener("click", function () { by(i, h.getAttribute("aria-sort") === "ascending" ? "descending" : "ascending"); });
      });
      var hash = decodeURIComponent(location.hash || "");
      if (t.id === "per-route" && hash.indexOf("#test:sort=") === 0) {
        var s = hash.slice(11).split(":"), col = -1;
        for (var i = 0; i < hs.length; i++) { if (hs[i].getAttribute("data-col") === s.slice(0, -1).join(":")) { col = i; } }
        if (col < 0) { throw new Error("no column " + s.slice(0, -1).join(":")); }
        by(col, s[s.length - 1] === "desc" ? "descending" : "ascending");
        var out = document.createElement("pre");
        out.id = "test-result";
        out.textContent = Array.prototype.map.call(tb.rows, function (r) { return r.getAttribute("data-key"); }).join("\n");
        document.body.appendChild(out);
      }
    });
  }
  // Each event marker of an opened drill-down, measured back to the frame it is drawn at
  // (`data-at-frame`): frame f of n sits at f / (n - 1) of the axis.
  function measure(root) {
    Array.prototype.forEach.call(root.querySelectorAll("svg.events-axis"), function (svg) {
      var axis = svg.querySelector(".axis").getBoundingClientRect(), n = +svg.getAttribute("data-frames");
      if (!(axis.width > 0)) { return; }
      Array.prototype.forEach.call(svg.querySelectorAll(".ev"), function (m) {
        var b = m.getBoundingClientRect(), x = m.tagName.toLowerCase() === "rect" ? b.left : b.left + b.width / 2;
        m.setAttribute("data-at-frame", Math.round((x - axis.left) / axis.width * Math.max(n - 1, 1)));
      });
    });
  }
  Array.prototype.forEach.call(document.querySelectorAll("details.route"), function (d) {
    d.addEventListener("toggle", function () { if (d.open) { measure(d); } });
  });
  var table = document.getElementById("routes");
  var status = document.getElementById("status");
  function fail(msg) { status.hidden = false; status.textContent = "error: " + msg; document.title = "SDS report [error]"; throw new Error(msg); }
  if (!table) { sortables(); if (status) { status.textContent = "ok"; document.title += " [ready]"; } return; }
  var body = table.tBodies[0];
  var heads = table.tHead.rows[0].cells;
  var rows = Array.prototype.slice.call(body.rows);
  function key(row, col) {
    var c = row.cells[col], v = c.getAttribute("data-v");
    if (v === null) { return c.textContent; }
    return v === "" ? NaN : parseFloat(v);
  }
  function sortBy(col, dir) {
    var sign = dir === "descending" ? -1 : 1;
    var sorted = rows.slice().sort(function (a, b) {
      var x = key(a, col), y = key(b, col);
      var xn = typeof x === "number", yn = typeof y === "number";
      if (xn && isNaN(x)) { return isNaN(y) ? 0 : 1; }   // empty cells last, both ways
      if (yn && isNaN(y)) { return -1; }
      var r = xn && yn ? x - y : String(x).localeCompare(String(y));
      return r === 0 ? (+a.getAttribute("data-i")) - (+b.getAttribute("data-i")) : sign * r;
    });
    for (var i = 0; i < heads.length; i++) { heads[i].removeAttribute("aria-sort"); }
    heads[col].setAttribute("aria-sort", dir);
    sorted.forEach(function (r) { body.appendChild(r); });
  }
  var filterBox = document.getElementById("filter"), stateBox = document.getElementById("state");
  function applyFilter() {
    var text = filterBox.value.toLowerCase(), st = stateBox.value, shown = 0;
    rows.forEach(function (r) {
      var ok = (!text || r.textContent.toLowerCase().indexOf(text) >= 0) &&
               (!st || r.getAttribute("data-state") === st);
      r.hidden = !ok; if (ok) { shown++; }
    });
    document.getElementById("shown").textContent = shown + " of " + rows.length + " routes";
  }
  function column(name) {
    for (var i = 0; i < heads.length; i++) { if (heads[i].getAttribute("data-col") === name) { return i; } }
    fail("no column " + name);
  }
  Array.prototype.forEach.call(heads, function (h, i) {
    h.addEventListener("click", function () {
      sortBy(i, h.getAttribute("aria-sort") === "ascending" ? "descending" : "ascending");
    });
  });
  filterBox.addEventListener("input", applyFilter);
  stateBox.addEventListener("change", applyFilter);
  body.addEventListener("click", function (e) {
    var a = e.target.closest("a[href^='#route-']");
    if (a) { var d = document.getElementById(a.getAttribute("href").slice(1)); if (d) { d.open = true; } }
  });
  applyFilter();
  // Self-checks: every row has its drill-down; as many rows as the report has routes.
  var expected = +table.getAttribute("data-routes");
  if (rows.length !== expected) { fail(rows.length + " rows, expected " + expected); }
  rows.forEach(function (r) {
    if (!document.getElementById(r.getAttribute("data-target"))) { fail("no drill-down for " + r.getAttribute("data-route")); }
  });
  var figs = document.querySelectorAll(".fig svg").length;
  if (figs !== +table.getAttribute("data-figures")) { fail(figs + " figures, expected " + table.getAttribute("data-figures")); }
  // The pictures above the tables: each laid out with a size (the browser test reads it).
  var pictures = 0;
  ["waterfall", "route-chart"].forEach(function (id) {
    var f = document.getElementById(id), svg = f && f.querySelector("svg");
    if (!svg) { return; }
    var b = svg.getBoundingClientRect();
    if (!(b.width > 0 && b.height > 0)) { fail(id + " is not laid out"); }
    f.setAttribute("data-rendered", Math.round(b.width) + "x" + Math.round(b.height));
    pictures++;
  });
  var h = decodeURIComponent(location.hash || "");
  if (h.indexOf("#test:") === 0) {
    h.slice(6).split(";").forEach(function (kv) {
      var p = kv.split("="), k = p[0], v = p.slice(1).join("=");
      if (k === "sort") { var s = v.split(":"); sortBy(column(s[0]), s[1] === "desc" ? "descending" : "ascending"); }
      if (k === "filter") { filterBox.value = v; applyFilter(); }
      if (k === "state") { stateBox.value = v; applyFilter(); }
      if (k === "open") { var d = document.getElementById(v); if (!d) { fail("no drill-down " + v); } d.open = true; measure(d); }
    });
    var out = document.createElement("pre");
    out.id = "test-result";
    out.textContent = Array.prototype.filter.call(body.rows, function (r) { return !r.hidden; })
      .map(function (r) { return r.getAttribute("data-route"); }).join("\n");
    document.body.appendChild(out);
  }
  // The table's width beside the room it has (the browser test checks it does not overflow).
  table.setAttribute("data-width", table.scrollWidth);
  table.setAttribute("data-room", table.parentNode.clientWidth);
  status.textContent = "ok: " + rows.length + " routes, " + figs + " figures, " + pictures + " pictures; checked " +
    Math.round(performance.now()) + " ms after navigation start";
  document.title += " [ready]";
})();
