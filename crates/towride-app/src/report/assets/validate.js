// towride validation report: the run's figures, the error metrics table, measured vs
// simulated per sensor (uPlot, one chart per comparison, cursor shared) and spectra.
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const app = document.getElementById("app");
  const charts = [];
  window.towrideCharts = charts;
  const [cm, cs] = D.colours;
  for (const c of D.comparisons) {
    c.t = decode(c.t);
    for (const ch of c.channels) {
      if (ch.measured) ch.measured = decode(ch.measured);
      if (ch.simulated) ch.simulated = decode(ch.simulated);
    }
  }
  for (const [text, colour] of D.header) app.append(el("p", { style: `color:${colour};margin:2px 0` }, text));

  // --- metrics
  app.append(el("h2", { id: "metrics" }, "Error metrics"));
  app.append(el("p", { class: "hint" }, "Rating: ISO/TS 18571-style (1 = identical; > 0.94 excellent, > 0.8 good, > 0.58 fair). Peaks and times on the recording's clock; RMS difference and correlation over the rated interval."));
  // Fixed decimals per kind of figure, and the ratings apart from the peaks and
  // differences: one table of every figure at five significant digits was wider than a
  // 1300 px window.
  const dec = (d) => (v) => (v == null || !isFinite(v) ? "–" : v.toFixed(d));
  const [r3, p2] = [dec(3), dec(2)];
  const ratings = [], peaks = [];
  for (const c of D.comparisons) {
    for (const ch of c.channels) {
      const f = ch.figures, r = f.rating;
      ratings.push([f.channel, c.label, r3(r.overall), r3(r.corridor), r3(r.phase), r3(r.magnitude), r3(r.slope)]);
      peaks.push([f.channel, c.label, p2(f.peak_measured_mps2), r3(f.t_peak_measured_s), p2(f.peak_simulated_mps2), r3(f.t_peak_simulated_s),
        r3(f.rms_diff_mps2), r3(f.correlation), r3(f.gain_ratio), f.clipped_samples]);
    }
  }
  app.append(el("div", { id: "metrics-box", style: "display:flex;flex-wrap:wrap;gap:0 32px;align-items:flex-start" },
    el("div", { style: "overflow-x:auto;max-width:100%" }, el("h3", {}, "Ratings"),
      table(["channel", "comparison", "rating", "corridor", "phase", "magnitude", "slope"], ratings)),
    el("div", { style: "overflow-x:auto;max-width:100%" }, el("h3", {}, "Peaks and differences"),
      table(["channel", "comparison", "peak measured [m/s²]", "at [s]", "peak simulated [m/s²]", "at [s]", "RMS difference [m/s²]", "correlation", "gain ratio", "clipped samples"], peaks))));
  app.append(table(["comparison", "speed [km/h]", "time shift [ms]", "mean rating"],
    D.comparisons.map((c) => [c.label, c.speed_kmh, c.shift_ms, c.mean_rating])));

  // --- overlays
  app.append(el("h2", { id: "overlays" }, "Measured and simulated"));
  app.append(el("p", { class: "hint" }, "Time from the obstacle as each comparison places it. Drag to zoom, double click to reset, wheel zooms time, shift + wheel pans; the cursor is shared by all charts."));
  const n = D.comparisons[0].channels.length;
  const w = Math.max(420, Math.min(700, (document.documentElement.clientWidth - 90) / D.comparisons.length));
  const measured = D.synthetic ? "measured (synthetic)" : "measured";
  const overlays = el("div", { id: "overlays-box" });
  app.append(overlays);
  for (let k = 0; k < n; k++) {
    const name = D.comparisons[0].channels[k].figures.channel;
    overlays.append(el("h3", {}, name));
    const row = el("div", { style: "display:flex;flex-wrap:wrap;gap:0 24px" });
    overlays.append(row);
    for (const c of D.comparisons) {
      const ch = c.channels[k];
      const box = el("div", { class: "chart" });
      row.append(el("div", {}, el("div", { class: "hint" }, `${c.label}: rating ${fmt(ch.figures.rating.overall)}`), box));
      charts.push(new uPlot({
        width: w, height: 260,
        cursor: { sync: { key: "t", setSeries: false }, drag: { x: true, y: false } },
        scales: { x: { time: false } },
        axes: [{ label: "time from obstacle [ms]", values: ticks }, { label: `${name} [m/s²]`, size: 70, values: ticks }],
        series: [{ label: "t [ms]", value: (u, v) => fmt(v) },
          { label: measured, stroke: cm, width: 2, value: (u, v) => fmt(v) },
          { label: "simulated", stroke: cs, width: 2, value: (u, v) => fmt(v) }],
        plugins: [wheel()],
      }, [c.t, ch.measured || [], ch.simulated || []], box));
    }
  }

  // --- spectra
  app.append(el("h2", { id: "spectra" }, "Spectra"));
  const P = D.psd;
  const primary = D.comparisons[D.comparisons.length - 1];
  const bin = P.f.length > 1 ? P.f[1] - P.f[0] : NaN;
  const tops = [["the recording's Nyquist frequency", P.recording_hz / 2], ["the simulation's Nyquist frequency", P.simulation_hz / 2], ["the acquisition low-pass cut-off", P.cutoff_hz]]
    .filter(([, v]) => isFinite(v) && v > 0);
  app.append(el("p", { class: "hint", id: "psd-hint" }, `Power spectral density of the ${primary.label} comparison's curves: Hann window over ` +
    (P.segments > 1 ? `${P.segments} half-overlapping segments of ${fmt(P.segment_s)} s` : `the whole compared window (${fmt(P.segment_s)} s)`) +
    `, resolution ${fmt(1 / P.segment_s)} Hz (1 / segment), drawn every ${fmt(bin)} Hz; shown up to ${fmt(P.band_hz)} Hz, the lowest of ` +
    tops.map(([what, v]) => `${what} (${fmt(v)} Hz)`).join(", ") + ": above it the two curves do not both carry data."));
  app.append(el("div", { style: "overflow-x:auto" }, table(["channel", "measured body [Hz]", "simulated body [Hz]", "measured wheel [Hz]", "simulated wheel [Hz]", "clipped samples", "simulated clipping"],
    D.channels.map((c) => [c.channel, c.measured_hz.body_hz ?? "–", c.simulated_hz.body_hz ?? "–", c.measured_hz.wheel_hz ?? "–", c.simulated_hz.wheel_hz ?? "–", c.clipped_samples, c.simulated_clipped_samples]))));
  const grid = el("div", { style: "display:flex;flex-wrap:wrap;gap:0 24px" });
  app.append(grid);
  const f = P.f.slice(1);
  P.channels.forEach((s, k) => {
    // A log axis over 12 decades at most: a symmetric run's lateral channel is round-off
    // (PSD ~1e-24), which carries no information and breaks uPlot's log ticks.
    const top = Math.max(0, ...[s.measured, s.simulated].filter(Boolean).flatMap((a) => a.slice(1)).filter((v) => v > 0));
    if (!(top > 0)) return;
    const pos = (a) => (a ? a.slice(1).map((v) => (v > 1e-12 * top ? v : null)) : f.map(() => null));
    const name = primary.channels[k].figures.channel;
    const box = el("div", { class: "chart" });
    grid.append(el("div", {}, el("h3", {}, name), box));
    charts.push(new uPlot({
      width: Math.max(420, Math.min(700, (document.documentElement.clientWidth - 90) / 2)), height: 260,
      scales: { x: { time: false, distr: 3, range: (u, a, b) => [Math.max(a, f[0]), Math.min(b, P.band_hz)] }, y: { distr: 3 } },
      axes: [{ label: "frequency [Hz]", values: logTicks }, { label: "PSD [(m/s²)²/Hz]", size: 80, values: logTicks }],
      series: [{ label: "f [Hz]", value: (u, v) => fmt(v) },
        { label: measured, stroke: cm, width: 2, value: (u, v) => fmt(v) },
        { label: "simulated", stroke: cs, width: 2, value: (u, v) => fmt(v) }],
      plugins: [wheel()],
    }, [f, pos(s.measured), pos(s.simulated)], box));
  });
  setTimeout(() => document.body.setAttribute("data-ready", String(charts.length)), 0);
})();
