// Shared by the run report and the comparison page: DOM helpers, number and tick
// formats, wheel zoom for uPlot, and the decoding of quantised signals.
"use strict";
// Signals come as integers and a scale (report::html::quantised).
const decode = (x) => x.q.map((q) => (q == null ? null : q * x.s));
const el = (tag, attrs, ...kids) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  for (const k of kids) e.append(k);
  return e;
};
const fmt = (v) => {
  if (v == null || !isFinite(v)) return "–";
  const a = Math.abs(v);
  if (a !== 0 && (a < 1e-3 || a >= 1e5)) return v.toExponential(4);
  return String(+v.toPrecision(5));
};
const table = (head, rows) =>
  el("table", {}, el("tr", {}, ...head.map((h) => el("th", {}, h))),
    ...rows.map((r) => el("tr", {}, ...r.map((c) => el("td", {}, typeof c === "number" ? fmt(c) : String(c))))));
// Tick labels: the fewest decimals that keep them distinct, exponents for very small
// or large values; on log axes each decade on its own.
const ticks = (u, splits) => {
  const v = splits.filter((x) => x != null);
  const big = Math.max(0, ...v.map(Math.abs));
  const tidy = (x) => (Object.is(x, -0) ? 0 : x);
  const distinct = (l) => new Set(l).size === l.length;
  if (big > 0 && (big < 1e-3 || big >= 1e6)) {
    for (let d = 0; d < 8; d++) {
      const l = splits.map((x) => (x == null ? "" : x === 0 ? "0" : x.toExponential(d).replace("e+", "e")));
      if (distinct(l)) return l;
    }
  }
  for (let d = 0; d < 10; d++) {
    const l = splits.map((x) => (x == null ? "" : String(tidy(+x.toFixed(d)))));
    if (distinct(l)) return l;
  }
  return splits.map((x) => (x == null ? "" : x.toExponential(4)));
};
const logTicks = (u, splits) =>
  splits.map((x) => (x == null ? "" : x >= 1e-2 && x < 1e5 ? String(+x.toPrecision(3)) : x.toExponential(0).replace("e+", "e")));
const width = () => Math.max(480, Math.min(1400, document.documentElement.clientWidth - 60));

// Wheel zooms time about the cursor; shift + wheel pans; drag zooms, double click resets.
const wheel = () => ({
  hooks: {
    ready: (u) => {
      u.over.addEventListener("wheel", (e) => {
        e.preventDefault();
        const a = u.scales.x.min, b = u.scales.x.max;
        if (e.shiftKey) {
          const d = (b - a) * 0.1 * Math.sign(e.deltaY || e.deltaX);
          u.setScale("x", { min: a + d, max: b + d });
          return;
        }
        const x = u.posToVal(u.cursor.left, "x");
        const f = e.deltaY < 0 ? 0.8 : 1.25;
        u.setScale("x", { min: x - (x - a) * f, max: x + (b - x) * f });
      }, { passive: false });
    },
  },
});

