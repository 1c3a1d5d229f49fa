// towride run report: builds the page from the JSON in #data with uPlot.
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  D.t = decode(D.t);
  for (const c of D.channels) c.v = decode(c.v);
  const S = D.summary;
  // A unit of the summary (SI, ASCII as in the CSV) in its display form (m/s²).
  const du = (u) => (D.units && D.units[u]) || u;
  const app = document.getElementById("app");
  const charts = [];
  window.towrideCharts = charts;

  // --- summary
  app.append(el("h2", { id: "summary" }, "Run summary"));
  const status = el("span", { class: S.status === "completed" ? "" : "failed" }, S.status);
  app.append(el("p", {}, status, ` · ${S.file} · ${fmt(S.t_reached_s)} of ${fmt(S.t_end_s)} s · ${S.samples} samples at ${fmt(S.sample_rate_hz)} Hz · ${fmt(S.wall_s)} s wall`));
  if (S.error) app.append(el("p", { class: "failed" }, `stopped at ${fmt(S.failed_at_s)} s: ${S.error}`));
  app.append(el("h3", {}, "Solver"));
  // Radau IIA has one order (5); the BDF's order varies step by step.
  const radau = S.method === "radau5";
  app.append(table(["method", "rtol", "steps", "rejected", "Newton iterations", "residuals", "Jacobians", "LU factorisations", radau ? "order" : "steps per order 1..5"],
    [[radau ? "Radau IIA" : "BDF", S.rtol.toExponential(), S.steps, S.rejected_steps, S.newton_iterations, S.residual_evals, S.jacobian_evals, S.lu_factorizations, radau ? "5" : (S.order_counts || []).join(" / ")]]));
  if (S.hitch_force) {
    const h = S.hitch_force;
    const opt = (v, d) => (v == null ? "-" : d(v));
    app.append(el("h3", {}, `Hitch force (${h.channel}, raw)`));
    app.append(table(["max [N]", "at [s]", "min [N]", "at [s]", "|peak| [N]", "at [s]", "RMS [N]", "dominant frequency [Hz]", "damping ratio of the ringing", "decay fitted [s]"],
      [[h.max_n, h.t_max_s, h.min_n, h.t_min_s, h.abs_peak_n, h.t_abs_peak_s, h.rms_n, opt(h.dominant_hz, fmt), opt(h.damping_ratio, (z) => `${fmt(100 * z)} %`),
        opt(h.decay, (d) => `${fmt(d.from_s)}-${fmt(d.to_s)} (${d.half_cycles} half cycles)`)]]));
  }
  // --- what produced the run: version, commit, command line, overrides in effect
  const P = S.produced_by;
  if (P) {
    app.append(el("h3", { id: "produced-by" }, "Produced by"));
    app.append(el("p", {}, `towride ${P.towride_version || "?"} (commit ${P.git_commit || "unknown"})` +
      (P.command_line && P.command_line.length ? ` · command line: ${P.command_line.join(" ")}` : "")));
    app.append(P.overrides.length
      ? table(["file", "path", "value", "written at", "layer"], P.overrides.map((o) => [o.file, o.path, o.value, o.origin, o.layer]))
      : el("p", { class: "hint" }, "No overrides: the run read its files as they are."));
  }
  // --- convergence verdict (run --check), failing channels first
  const V = S.convergence;
  app.append(el("h3", { id: "convergence" }, "Convergence"));
  if (!V) {
    app.append(el("p", { class: "hint" }, "Not checked: `towride run --check` runs the scene again at rtol and atol ten times tighter and judges every reported channel's max, min and RMS."));
  } else {
    const below = V.below_floor || [];
    const n = Object.keys(V.channels).length - below.length;
    const pct = (x) => `${(100 * x).toFixed(2)} %`;
    // The companion's rtol is rtol / 10 in binary floating point (1e-5 / 10 = 1.0000000000000002e-6).
    const sci = (x) => Number(x.toPrecision(12)).toExponential();
    app.append(el("p", { class: V.converged ? "" : "failed" }, V.converged
      ? `All ${n} judged channels converged: max, min and RMS within ${pct(V.threshold)} of a run at rtol ${sci(V.check_rtol)} (this run: ${sci(V.rtol)}; ${V.check_steps} steps, ${fmt(V.check_wall_s)} s wall).`
      : `${V.failing.length} of ${n} channels NOT converged (differences over ${pct(V.threshold)} against a run at rtol ${sci(V.check_rtol)}; this run: ${sci(V.rtol)}): ${V.failing.join(", ")}. Their numbers on this page depend on the tolerance.`));
    if (below.length) app.append(el("p", { class: "hint" }, `${below.length} channels stay within their unit's floor in both runs (round-off, not results; not judged): ${below.join(", ")}.`));
    // Failing first; within each, the summary's natural order (the sort is stable).
    const names = Object.keys(V.channels).sort((a, b) => V.channels[a].converged - V.channels[b].converged);
    // Per channel, folded away when everything converged.
    const box = el("details", V.converged ? {} : { open: "" }, el("summary", {}, "per channel: differences relative to max(|value|, floor)"));
    box.append(table(["channel", "unit", "max diff", "min diff", "RMS diff", "floor", "verdict"],
      names.map((k) => { const c = V.channels[k]; return [k, du(c.unit), pct(c.max_diff), pct(c.min_diff), pct(c.rms_diff), fmt(c.floor), c.below_floor ? "below floor" : c.converged ? "converged" : "NOT converged"]; })));
    app.append(box);
  }
  // --- 3D view, its time cursor shared with the charts both ways
  let player = null, syncing = false;
  const follow = () => ({
    hooks: {
      setCursor: (u) => {
        const l = u.cursor.left;
        if (syncing || !player || l == null || l < 0) return;
        player.pause();
        player.setTime(u.posToVal(l, "x"), true);
      },
    },
  });
  const toCharts = (t) => {
    syncing = true;
    for (const u of charts) u.setCursor({ left: u.valToPos(t, "x"), top: u.cursor.top > 0 ? u.cursor.top : 10 });
    syncing = false;
  };
  if (D.view) player = runView(D.view, app, toCharts);
  // --- time histories
  app.append(el("h2", { id: "histories" }, "Time histories"));
  app.append(el("p", { class: "hint" }, "Drag to zoom, double click to reset, mouse wheel zooms time, shift + wheel pans; click a legend entry to hide or show it. The time cursor is shared by all charts."));
  const A = S.acquisition;
  app.append(el("p", { id: "shown", class: "hint" }, A
    ? `Shown: accelerometers (acc_*, trailer_ax) band-limited, as the instrument saw them: <channel>${A.suffix}, through the scene's acquisition chain (${A.description}, filtered on a ${fmt(A.grid_rate_hz)} Hz grid); their raw channels are in the legends, hidden (click to show). Forces and deflections (hitch_f*, hitch_bracket_*, hitch_deflection_*) are shown raw, their band-limited twins hidden in the legends.`
    : "Shown: raw channels (the scene declares no acquisition chain)."));
  const t = D.t;
  for (const g of D.groups) {
    const box = el("div", { class: "chart" });
    app.append(el("h3", {}, g.title), box);
    const opts = {
      width: width(), height: 280,
      cursor: { sync: { key: "t", setSeries: false }, drag: { x: true, y: false } },
      scales: { x: { time: false } },
      axes: [{ label: "time [s]", values: ticks }, { label: g.y, size: 70, values: ticks }],
      series: [{ label: "t [s]", value: (u, v) => fmt(v) }].concat(g.series.map((s) => ({
        label: `${D.channels[s.ch].name} [${D.channels[s.ch].du}]`,
        stroke: s.colour, width: s.width, dash: s.dash ? [8, 4] : undefined, show: s.show !== false,
        value: (u, v) => fmt(v),
      }))),
      plugins: [wheel(), follow()],
    };
    const data = [t].concat(g.series.map((s) => D.channels[s.ch].v));
    charts.push(new uPlot(opts, data, box));
  }

  // --- spectra
  app.append(el("h2", { id: "spectra" }, "Spectra"));
  const pick = el("select", { id: "psd-channel" });
  D.channels.forEach((c, k) => { if (D.psd.density[k]) pick.append(el("option", { value: k }, `${c.name} [${c.du}]`)); });
  app.append(el("p", { class: "hint" }, `Welch power spectral density: Hann window, ${D.psd.segment} samples per segment (${fmt(D.psd.fs / D.psd.segment)} Hz resolution), half overlap. Channel: `, pick));
  const psdBox = el("div", { class: "chart" });
  app.append(psdBox);
  let psdChart = null;
  const drawPsd = () => {
    const k = +pick.value;
    const c = D.channels[k];
    // Log axes: the zero-frequency bin and densities 12 decades below the top (round-off,
    // which breaks uPlot's log ticks) are left out.
    const f = D.psd.f.slice(1);
    const top = Math.max(0, ...D.psd.density[k].slice(1).filter((v) => v > 0));
    const p = D.psd.density[k].slice(1).map((v) => (v > 1e-12 * top ? v : null));
    if (psdChart) psdChart.destroy();
    psdChart = new uPlot({
      width: width(), height: 320,
      scales: { x: { time: false, distr: 3 }, y: { distr: 3 } },
      axes: [{ label: "frequency [Hz]", values: logTicks }, { label: `PSD [(${c.du})²/Hz]`, size: 80, values: logTicks }],
      series: [{ label: "f [Hz]", value: (u, v) => fmt(v) },
        { label: `${c.name}`, stroke: "#0072b2", width: 2, value: (u, v) => fmt(v) }],
      plugins: [wheel()],
    }, [f, p], psdBox);
    charts.psd = psdChart;
  };
  pick.addEventListener("change", drawPsd);
  if (pick.options.length) {
    const hf = [...pick.options].find((o) => D.channels[+o.value].name === "hitch_fx");
    if (hf) pick.value = hf.value;
    drawPsd();
  }

  // --- solver steps
  app.append(el("h2", { id: "steps" }, "Solver step size and order"));
  if (D.steps.t.length) {
    const box = el("div", { class: "chart" });
    app.append(box);
    charts.push(new uPlot({
      width: width(), height: 300,
      cursor: { drag: { x: true, y: false } },
      scales: { x: { time: false }, h: { distr: 3 }, o: { range: [0.5, 5.5] } },
      axes: [{ label: "time [s]", values: ticks }, { scale: "h", label: "step [s] (log)", size: 70, values: logTicks },
        { scale: "o", side: 1, label: "order", grid: { show: false }, values: ticks }],
      series: [{ label: "t [s]", value: (u, v) => fmt(v) },
        { label: "step [s]", scale: "h", stroke: "#0072b2", width: 1, value: (u, v) => fmt(v), points: { show: true, size: 3 } },
        { label: "order", scale: "o", stroke: "#d55e00", width: 1, paths: uPlot.paths.stepped({ align: 1 }), value: (u, v) => fmt(v) }],
      plugins: [wheel(), follow()],
    }, [D.steps.t, D.steps.h, D.steps.order], box));
  } else {
    app.append(el("p", {}, "no steps recorded"));
  }
  app.append(el("h2", { id: "details" }, "Run summary: details"));
  // --- ride comfort (ISO 2631-1) at the floor point under the driver's seat
  if (S.comfort) {
    const C = S.comfort;
    app.append(el("h3", { id: "comfort" }, "Ride comfort (ISO 2631-1)"));
    app.append(el("p", {}, `${C.point}. Vibration total value a_v = ${C.total_value_m_s2 == null ? "-" : fmt(C.total_value_m_s2) + " m/s²"} (k = 1, 1, 1).`));
    app.append(table(["channel", "axis", "weighting", "a_w [m/s²]", "VDV [m/s^1.75]", "MTVV [m/s²]", "peak [m/s²]", "crest factor", "transient"],
      C.axes.map((a) => [a.channel, a.axis, a.weighting.replace("w", "W"), a.rms_m_s2, a.vdv_m_s1_75, a.mtvv_m_s2, a.peak_m_s2, a.crest_factor, a.below_resolution ? "round-off (peak < 0.05 m/s²)" : a.transient ? "yes" : "no"])));
    app.append(el("p", { class: "hint" }, `Over the whole record (${fmt(C.axes[0].duration_s)} s); ${C.note}.`));
  }
  // --- and at the seat surface, when the body file gives a seat
  if (S.comfort_seat) {
    const Q = S.comfort_seat, C = Q.comfort, m = Q.seat;
    app.append(el("h3", { id: "comfort_seat" }, "Ride comfort at the seat surface (ISO 2631-1)"));
    app.append(el("p", {}, `${C.point}. Vibration total value a_v = ${C.total_value_m_s2 == null ? "-" : fmt(C.total_value_m_s2) + " m/s²"} (k = 1, 1, 1).`));
    app.append(table(["channel", "axis", "weighting", "a_w [m/s²]", "VDV [m/s^1.75]", "MTVV [m/s²]", "peak [m/s²]", "crest factor", "transient"],
      C.axes.map((a) => [a.channel, a.axis, a.weighting.replace("w", "W"), a.rms_m_s2, a.vdv_m_s1_75, a.mtvv_m_s2, a.peak_m_s2, a.crest_factor, a.below_resolution ? "round-off (peak < 0.05 m/s²)" : a.transient ? "yes" : "no"])));
    app.append(table(["seat model", "value"], [
      ["cushion stiffness [N/m]", m.cushion_stiffness_n_m],
      ["cushion damping [N s/m]", m.cushion_damping_n_s_m],
      ["occupant mass moving with the seat [kg]", m.frame_mass_kg],
      ["occupant mass on its spring [kg]", m.moving_mass_kg],
      ["occupant spring [N/m]", m.occupant_stiffness_n_m],
      ["occupant damper [N s/m]", m.occupant_damping_n_s_m],
      ["largest vertical transmissibility [-]", Q.peak_transmissibility],
      ["at [Hz]", Q.resonance_hz],
      ["SEAT value z, a_w seat / a_w floor [-]", Q.seat_value_rms],
      ["VDV seat / VDV floor, z [-]", Q.seat_value_vdv]]));
    const tb = el("div", { class: "chart" });
    app.append(tb);
    charts.push(new uPlot({
      width: width(), height: 260,
      scales: { x: { time: false, distr: 3 } },
      axes: [{ label: "frequency [Hz]", values: logTicks }, { label: "|a_seat / a_floor| [-]", size: 60, values: ticks }],
      series: [{ label: "f [Hz]", value: (u, v) => fmt(v) },
        { label: "vertical seat transmissibility", stroke: "#0072b2", width: 2, value: (u, v) => fmt(v) }],
      plugins: [wheel()],
    }, [Q.transmissibility.map((p) => p[0]), Q.transmissibility.map((p) => p[1])], tb));
    app.append(el("p", { class: "hint" }, "The seat is a filter on the floor's vertical acceleration (cushion spring and damper under the occupant's apparent mass, Fairley & Griffin 1989), not coupled back into the car; fore-aft and lateral pass through unchanged. docs/comfort.md gives the sources and what is assumed."));
  }
  if ((S.lift_off || []).length) {
    app.append(el("h3", {}, "Wheels off the road"));
    app.append(table(["wheel", "from [s]", "to [s]", "for [s]"],
      S.lift_off.map((l) => [l.wheel, l.start_s, l.end_s == null ? "end" : l.end_s, l.duration_s])));
  }
  for (const m of S.modal_energy || []) {
    app.append(el("h3", {}, `Strain energy of '${m.body}' by mode (peak total ${fmt(m.peak_total_j)} J)`));
    app.append(table(["mode", "frequency [Hz]", "peak [J]", "share of peak", "share of integral", "kept at 1 %"],
      m.modes.map((q) => [q.number, q.frequency_hz, q.peak_j, q.share_peak, q.share_integral, m.kept_at_1_percent.includes(q.number) ? "yes" : ""])));
  }
  // Each raw channel with its band-limited twin, the one shown first on top.
  const chans = S.channels || {};
  const rows = [];
  const row = (n, c) => [n, c.signal === "band_limited" ? (A ? `band-limited, ${fmt(A.cutoff_hz)} Hz` : "band-limited") : "raw",
    du(c.unit), c.min, c.t_min, c.max, c.t_max, c.abs_peak, c.t_abs_peak];
  for (const [n, c] of Object.entries(chans)) {
    if (c.signal !== "raw") continue;
    const t = c.twin && chans[c.twin];
    if (t && t.shown) rows.push(row(c.twin, t), row(n, c));
    else if (t) rows.push(row(n, c), row(c.twin, t));
    else rows.push(row(n, c));
  }
  app.append(el("h3", { id: "extremes" }, "Channel extremes"));
  app.append(el("p", { class: "hint" }, "|peak| = max(|max|, |min|), the larger magnitude; which side it is on shows in max and min." +
    (A ? ` Band-limited: through the scene's acquisition chain (${A.description}); each pair listed with the one shown in the charts first.` : "")));
  app.append(table(["channel", "signal", "unit", "min", "at [s]", "max", "at [s]", "|peak|", "at [s]"], rows));

  // For the browser test: per chart, the canvas pixels in colour (the traces; axes,
  // grid and text are grey).
  // uPlot draws in a microtask after construction: count after it.
  setTimeout(() => {
  if (player) player.ready();
  const all = charts.concat(psdChart ? [psdChart] : []);
  const coloured = all.map((u) => {
    const px = u.ctx.getImageData(0, 0, u.ctx.canvas.width, u.ctx.canvas.height).data;
    let n = 0;
    for (let i = 0; i < px.length; i += 4) {
      const hi = Math.max(px[i], px[i + 1], px[i + 2]), lo = Math.min(px[i], px[i + 1], px[i + 2]);
      if (px[i + 3] > 0 && hi - lo > 40) n++;
    }
    return n;
  });
  document.body.setAttribute("data-coloured-pixels", coloured.join(","));
  document.body.setAttribute("data-ready", String(all.length));
  // Built after load: follow a link to a section (#spectra) now.
  const target = location.hash && document.getElementById(location.hash.slice(1));
  if (target) target.scrollIntoView();
  }, 0);
})();

// The run's 3D view: poses interpolated linearly between the recorded frames
// (quaternions normalised), the modal deformation magnified by the factor in the page.
function runView(V, app, toCharts) {
  app.append(el("h2", { id: "view" }, "Animation"));
  app.append(el("p", { class: "hint" }, `Bodies as boxes with their inertia and rods to their hardpoints, wheels with tyres, struts for springs, dampers and bushings, the road with the obstacle, red dots at the tyre contacts. ${V.frames.t.q.length} poses. Drag to turn the view, wheel to zoom; the time cursor follows the charts (hover a chart) and moves theirs.`));
  const host = el("div", { class: "view" });
  app.append(host);
  const view = View3D(V, host, { width: width(), height: 480 });
  if (!view) return null;
  const ft = decode(V.frames.t), Q = V.frames.q.map(decode);
  let k = 0, w = 0;
  const lerp = (c) => Q[c][k] * (1 - w) + Q[c][Math.min(k + 1, ft.length - 1)] * w;
  view.pose = (b) => {
    const o = V.bodies[b].qo;
    const eta = [];
    for (let j = 0; j < V.bodies[b].nm; j++) eta.push(lerp(o + 7 + j));
    return { r: [lerp(o), lerp(o + 1), lerp(o + 2)], p: [lerp(o + 3), lerp(o + 4), lerp(o + 5), lerp(o + 6)], eta };
  };
  // Magnification: the largest FE-node deformation over the run drawn as 0.1 m.
  let big = 0;
  V.bodies.forEach((b) => {
    if (!b.flex) return;
    for (let f = 0; f < ft.length; f++) for (let n = 0; n < b.flex.pts.length; n++) {
      let x = 0, y = 0, z = 0;
      for (let j = 0; j < b.nm; j++) {
        const e = Q[b.qo + 7 + j][f], s = b.flex.shapes[j][n];
        x += e * s[0]; y += e * s[1]; z += e * s[2];
      }
      big = Math.max(big, Math.hypot(x, y, z));
    }
  });
  const nice = (v) => { const p = Math.pow(10, Math.floor(Math.log10(v))); return [1, 2, 5, 10].map((m) => m * p).find((m) => m >= v); };
  view.mag = big > 0 ? nice(0.1 / big) : 1;
  const mag = el("input", { id: "view-mag", type: "number", min: 0, step: "any", value: view.mag, style: "width:80px" });
  const show = (t, quiet) => {
    let lo = 0, hi = ft.length - 1;
    while (hi - lo > 1) { const m = (lo + hi) >> 1; if (ft[m] <= t) lo = m; else hi = m; }
    k = lo;
    w = ft.length > 1 ? Math.max(0, Math.min(1, (t - ft[lo]) / (ft[lo + 1] - ft[lo]))) : 0;
    view.draw();
    if (!quiet) toCharts(t);
  };
  const player = Player(ft[0], ft[ft.length - 1], show, [0.02, 0.05, 0.1, 0.25, 0.5, 1]);
  mag.addEventListener("change", () => { view.mag = +mag.value || 0; view.draw(); });
  player.bar.append(" deformation ×", mag, big > 0 ? ` (largest FE-node deformation ${fmt(big * 1e3)} mm)` : "");
  host.prepend(player.bar);
  window.towrideView = { view, player };
  // For the browser test: the image at two times; then the time the link asks for
  // (#view-t=0.5).
  player.ready = () => {
    const a = ft[0] + 0.05 * (ft[ft.length - 1] - ft[0]), b = ft[0] + 0.5 * (ft[ft.length - 1] - ft[0]);
    player.setTime(a, true);
    const pa = view.probe();
    player.setTime(b, true);
    const pb = view.probe();
    document.body.setAttribute("data-view-pixels", `${pa.join(",")};${pb.join(",")}`);
    const m = /view-t=([0-9.eE+-]+)/.exec(location.hash);
    player.setTime(m ? +m[1] : ft[0], !m);
  };
  return player;
}
