// towride comparison page: overlays one channel of every run (uPlot) and tabulates the
// differences against the first run.
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const C = D.comparison;
  const app = document.getElementById("app");
  for (const r of D.runs) {
    r.t = decode(r.t);
    for (const c of Object.values(r.channels)) c.v = decode(c.v);
  }
  const colours = ["#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#f0e442"];
  const pick = el("select", { id: "channel" });
  for (const n of C.channels) pick.append(el("option", { value: n }, n));
  app.append(el("p", { class: "hint" }, "Channel: ", pick, " — drag to zoom, double click to reset, wheel zooms time, shift + wheel pans."));
  const box = el("div", { class: "chart" });
  app.append(box);
  let chart = null;
  // Runs sampled on different grids: one x array of every run's times, each run's
  // values where it has a sample (uPlot joins across the gaps).
  const draw = () => {
    const n = pick.value;
    const all = [...new Set(D.runs.flatMap((r) => r.t))].sort((a, b) => a - b);
    const at = new Map(all.map((t, k) => [t, k]));
    const data = [all].concat(D.runs.map((r) => {
      const y = new Array(all.length).fill(undefined);
      r.t.forEach((t, k) => { y[at.get(t)] = r.channels[n].v[k]; });
      return y;
    }));
    if (chart) chart.destroy();
    const unit = D.runs[0].channels[n].unit;
    chart = new uPlot({
      width: width(), height: 360,
      cursor: { drag: { x: true, y: false } },
      scales: { x: { time: false } },
      axes: [{ label: "time [s]", values: ticks }, { label: `${n} [${unit}]`, size: 70, values: ticks }],
      series: [{ label: "t [s]", value: (u, v) => fmt(v) }].concat(D.runs.map((r, i) => ({
        label: r.label, stroke: colours[i % colours.length], width: 2, spanGaps: true,
        dash: i >= colours.length ? [8, 4] : undefined, value: (u, v) => fmt(v),
      }))),
      plugins: [wheel()],
    }, data, box);
  };
  pick.addEventListener("change", draw);
  const hf = C.channels.includes("hitch_fx") ? "hitch_fx" : C.channels[0];
  if (hf) { pick.value = hf; draw(); }
  app.append(el("h2", {}, `Differences against ${C.runs[0]}`));
  app.append(el("p", { class: "hint" }, `Like with like: each run's max, min and |peak| = max(|max|, |min|) against ${C.runs[0]}'s; a difference is this run's less ${C.runs[0]}'s.`));
  if (C.not_comparable.length) {
    const n = C.not_comparable.reduce((k, x) => k + x.channels.length, 0);
    app.append(el("p", { class: "hint" }, `${n} modal coordinates are left out: not comparable (different modal bases), see `,
      el("a", { href: "#not-comparable" }, "Not comparable"), " below."));
  }
  app.append(table(["channel", "unit", "run", `max ${C.runs[0]}`, "max", "max difference", `min ${C.runs[0]}`, "min", "min difference",
    `|peak| ${C.runs[0]}`, "|peak|", "|peak| difference", "RMS difference", "convergence (run --check)"],
    // The unit as the plot shows it (m/s²): the channel data carry the display form.
    C.differences.map((d) => [d.channel, (D.runs[0].channels[d.channel] || {}).unit || d.unit, d.run, d.reference_max, d.max, d.max_difference, d.reference_min, d.min, d.min_difference,
      d.reference_abs_peak, d.abs_peak, d.abs_peak_difference, d.rms_difference,
      d.converged == null ? "not checked" : d.converged ? "converged" : "NOT converged"])));
  // Modal coordinates of another Craig-Bampton basis: amplitudes of other mode shapes,
  // left out of the table above.
  if (C.not_comparable.length) {
    app.append(el("h2", { id: "not-comparable" }, "Not comparable"));
    app.append(el("p", { class: "hint" }, "Modal coordinates are amplitudes of a run's own mode shapes: across different modal bases (another hitch variant, other modes kept) they mean nothing, so they are not in the table of differences."));
    app.append(table(["channels", "run", "", "bases"], C.not_comparable.map((n) =>
      [n.channels.length > 1 ? `${n.channels[0]} … ${n.channels[n.channels.length - 1]} (${n.channels.length})` : n.channels.join(""),
        n.run, n.reason, n.detail])));
  }
  if (C.conversions.length) {
    app.append(el("h2", {}, "Units converted"));
    app.append(table(["channel", "run", "read in", "compared in", "factor"],
      C.conversions.map((v) => [v.channel, v.run, v.from, v.to, v.factor])));
  }
  setTimeout(() => document.body.setAttribute("data-ready", chart ? "1" : "0"), 0);
})();
