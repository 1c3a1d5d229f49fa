// towride sweep page: the table of cases (each linked to its report when kept) and
// every figure against a chosen swept parameter, one curve per combination of the
// others (uPlot).
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const T = D.table;
  const app = document.getElementById("app");
  const charts = [];
  window.towrideCharts = charts;
  const colours = ["#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#f0e442"];
  const done = T.rows.filter((r) => r.status === "completed").length;
  const kept = T.rows.filter((r) => r.link).length;
  app.append(el("p", {}, `${T.rows.length} cases: ${done} completed, ${T.rows.length - done} failed or interrupted; ` +
    (kept ? `${kept} with their own report (histories kept).` : "histories not kept (run the sweep with --keep-histories to link each case's report).")));
  // The convergence verdicts of a sweep run with --check, said before any figure.
  const cv = T.figures.indexOf("converged [-]");
  if (cv >= 0) {
    const judged = T.rows.filter((r) => r.figures[cv] != null);
    const bad = judged.filter((r) => r.figures[cv] !== 1);
    app.append(el("p", { id: "convergence", class: bad.length ? "failed" : "" }, bad.length
      ? `Convergence (--check): ${bad.length} of ${judged.length} cases NOT converged (cases ${bad.map((r) => r.case).join(", ")}): some of their figures depend on the tolerance; the case's own run --check names the channels.`
      : `Convergence (--check): all ${judged.length} checked cases converged.`));
  }
  if (T.figures.some((f) => / (abs_peak|max|min) \[/.test(f)))
    app.append(el("p", { id: "naming", class: "hint" }, "Figures: max and min of a channel, abs_peak = max(|max|, |min|) (its larger magnitude, whichever side); <channel>_lp<fc>: the channel through the scene's acquisition low-pass at fc Hz, as the instrument saw it (a case's summary.json names the filter)."));

  // --- plots
  app.append(el("h2", { id: "plots" }, "Figures against a swept parameter"));
  const grid = el("div", { id: "grid", style: "display:flex;flex-wrap:wrap;gap:8px 24px" });
  if (D.x < 0) {
    app.append(el("p", { class: "hint" }, "No swept parameter varies: nothing to plot against."));
  } else {
    const pick = el("select", { id: "xparam" });
    T.parameters.forEach((p, i) => pick.append(el("option", { value: String(i) }, p)));
    pick.value = String(D.x);
    app.append(el("p", { class: "hint" }, "x axis: ", pick,
      " — one curve per value of the other parameters; completed cases only. Click a legend entry to hide its curve; drag to zoom, double click to reset."));
    app.append(grid);
    const draw = () => {
      for (const c of charts) c.destroy();
      charts.length = 0;
      grid.textContent = "";
      const x = +pick.value;
      // Non-numeric values (arrays, strings) are placed by their order in the sweep.
      const labels = [...new Set(T.rows.map((r) => r.values[x]))];
      const xv = (r) => (D.numeric[x] ? +r.values[x] : labels.indexOf(r.values[x]));
      const xs = [...new Set(T.rows.map(xv))].sort((a, b) => a - b);
      const groups = new Map();
      for (const r of T.rows) {
        const key = T.parameters.map((p, i) => (i === x ? null : `${p} = ${r.values[i]}`)).filter((s) => s).join(", ");
        if (!groups.has(key)) groups.set(key, []);
        groups.get(key).push(r);
      }
      const w = Math.max(420, Math.min(680, (document.documentElement.clientWidth - 90) / 2));
      T.figures.forEach((name, f) => {
        const data = [xs];
        for (const rows of groups.values()) {
          const y = xs.map(() => null);
          for (const r of rows) if (r.status === "completed" && r.figures[f] != null) y[xs.indexOf(xv(r))] = r.figures[f];
          data.push(y);
        }
        const box = el("div", { class: "chart" });
        grid.append(el("div", {}, el("h3", {}, name), box));
        const xaxis = { label: T.parameters[x], values: ticks };
        if (!D.numeric[x]) {
          xaxis.splits = () => xs;
          xaxis.values = (u, s) => s.map((v) => labels[v] ?? "");
        }
        charts.push(new uPlot({
          width: w, height: 260,
          cursor: { drag: { x: true, y: false } },
          scales: { x: { time: false } },
          // The chart's title names the figure; the axis gives its unit.
          axes: [xaxis, { label: (name.match(/\[[^\]]*\]$/) || [name])[0], size: 70, values: ticks }],
          series: [{ label: T.parameters[x], value: (u, v) => (D.numeric[x] ? fmt(v) : labels[v] ?? "") }]
            .concat([...groups.keys()].map((k, i) => ({
              label: k || name, stroke: colours[i % colours.length], width: 2, spanGaps: true,
              dash: i >= colours.length ? [8, 4] : undefined,
              points: { show: true, size: 7, fill: colours[i % colours.length] },
              value: (u, v) => fmt(v),
            }))),
        }, data, box));
      });
    };
    pick.addEventListener("change", draw);
    draw();
  }
  if (D.png) app.append(el("p", { class: "hint" }, "The key figures as a picture: ", el("a", { href: D.png }, D.png)));

  // --- table (click a heading to sort)
  app.append(el("h2", { id: "cases" }, "Cases"));
  const head = ["case"].concat(T.parameters, ["status", "report"], T.figures, ["error"]);
  const cells = (r) => [r.case].concat(r.values, [r.status, r.link || ""], r.figures.map((v) => (v == null ? "" : v)), [r.error]);
  const box = el("div", { style: "overflow-x:auto" });
  app.append(box);
  let order = T.rows.slice();
  let by = -1, dir = 1;
  const render = () => {
    const tb = el("table", { id: "cases-table" });
    const tr = el("tr", {});
    head.forEach((h, k) => {
      const th = el("th", { style: "cursor:pointer" }, h + (k === by ? (dir > 0 ? " ▲" : " ▼") : ""));
      th.addEventListener("click", () => {
        dir = by === k ? -dir : 1;
        by = k;
        const key = (r) => cells(r)[k];
        order.sort((a, b) => {
          const p = key(a), q = key(b);
          const c = typeof p === "number" && typeof q === "number" ? p - q : String(p).localeCompare(String(q), undefined, { numeric: true });
          return dir * c;
        });
        render();
      });
      tr.append(th);
    });
    tb.append(tr);
    for (const r of order) {
      const row = el("tr", {});
      cells(r).forEach((c, k) => {
        let v = typeof c === "number" ? fmt(c) : String(c);
        if (head[k] === "report") v = r.link ? el("a", { href: r.link }, "report") : "";
        if (head[k] === "status" && c !== "completed") v = el("span", { class: "failed" }, c);
        row.append(el("td", {}, v));
      });
      tb.append(row);
    }
    box.textContent = "";
    box.append(tb);
  };
  render();
  setTimeout(() => {
    document.body.setAttribute("data-ready", String(charts.length));
    // Built after load: follow a link to a section (#cases) now.
    const target = location.hash && document.getElementById(location.hash.slice(1));
    if (target) target.scrollIntoView();
  }, 0);
})();
