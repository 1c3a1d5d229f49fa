// towride linear report: the mode table (each mode named by its dominant motion) and the
// 3D view animating the selected mode shape at an exaggerated amplitude.
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const V = D.view;
  const app = document.getElementById("app");
  const zero = D.modes.filter((m) => m.kind === "zero"), unstable = D.modes.filter((m) => m.kind === "unstable");
  app.append(el("p", {}, `${D.dof} degrees of freedom and ${D.first_order_states} first-order states (tyres, controllers): ${D.eigenvalues} eigenvalues, ${D.modes.length} modes (a conjugate pair listed once) · stiffness ratio S = ${D.stiffness_ratio == null ? "undefined" : fmt(D.stiffness_ratio)}`));
  if (unstable.length) app.append(el("p", { class: "failed", id: "unstable" }, `UNSTABLE roots of this frozen state: ${unstable.map((m) => `mode ${m.index} ${m.name}, growth rate ${fmt(m.real_1_per_s)} 1/s (doubles in ${fmt(m.doubling_time_s)} s)`).join("; ")}.`));

  // --- the view
  app.append(el("h2", { id: "view" }, "Mode shapes"));
  app.append(el("p", { class: "hint" }, "The selected mode's shape (the phase with the largest real part) drawn as a sine at one cycle per second whatever its frequency; the amplitude is the largest displacement of any body point or FE node. Drag to turn the view, wheel to zoom; click a row of the table to show its mode."));
  const host = el("div", { class: "view" });
  app.append(host);
  const view = View3D(V, host, { width: width(), height: 440, dist: 7 });
  const pick = el("select", { id: "mode" });
  V.modes.forEach((m, k) => pick.append(el("option", { value: k }, m.label)));
  const amp = el("input", { id: "mode-amp", type: "number", min: 0, step: "any", value: 0.08, style: "width:80px" });
  let s = 0, mode = null, scale = 0;
  // Largest displacement of the shape: a body's translation plus its rotation times the
  // reach of its box or hardpoints, and the FE nodes of a modal body.
  const reach = V.bodies.map((b, k) => {
    let r = 0.5 * Math.hypot(...b.box);
    V.markers.forEach((m) => { if (m.b === k) r = Math.max(r, Math.hypot(...m.p)); });
    return r;
  });
  const largest = (v) => {
    let big = 0;
    V.bodies.forEach((b, k) => {
      const o = V.vo[k];
      const u = Math.hypot(v[o], v[o + 1], v[o + 2]), w = Math.hypot(v[o + 3], v[o + 4], v[o + 5]);
      big = Math.max(big, u + w * reach[k]);
      if (b.flex) for (let n = 0; n < b.flex.pts.length; n++) {
        let x = 0, y = 0, z = 0;
        for (let j = 0; j < b.nm; j++) {
          const e = v[o + 6 + j], sh = b.flex.shapes[j][n];
          x += e * sh[0]; y += e * sh[1]; z += e * sh[2];
        }
        big = Math.max(big, u + w * reach[k] + Math.hypot(x, y, z));
      }
    });
    return big;
  };
  const select = (k) => {
    mode = V.modes[k];
    pick.value = String(k);
    const big = largest(mode.v);
    scale = big > 0 ? +amp.value / big : 0;
    if (view) view.draw();
  };
  if (view) {
    view.mag = 1;
    view.pose = (b) => {
      const o = V.bodies[b].qo, vo = V.vo[b], q = V.q0, v = mode ? mode.v : [];
      const a = mode ? s * scale : 0;
      const d = (i) => (mode ? a * v[vo + i] : 0);
      // p0 * (1, omega/2): the rotation about body axes.
      const [w1, x1, y1, z1] = [q[o + 3], q[o + 4], q[o + 5], q[o + 6]];
      const [w2, x2, y2, z2] = [1, d(3) / 2, d(4) / 2, d(5) / 2];
      const p = [w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2];
      const eta = [];
      for (let j = 0; j < V.bodies[b].nm; j++) eta.push(q[o + 7 + j] + d(6 + j));
      return { r: [q[o] + d(0), q[o + 1] + d(1), q[o + 2] + d(2)], p, eta };
    };
    const player = Player(0, 1, (t) => { s = Math.sin(2 * Math.PI * t); view.draw(); }, [1, 0.5, 0.25]);
    player.bar.prepend("mode ", pick, " amplitude [m] ", amp, " ");
    host.prepend(player.bar);
    pick.addEventListener("change", () => select(+pick.value));
    amp.addEventListener("change", () => select(+pick.value));
    window.towrideView = { view, player, select };
    // Opens on `#mode=N` (the mode numbered N in the table) or the first oscillation
    // with a shape, not on a zero root. Browser test: the image at two phases.
    if (V.modes.length) {
      const m = /mode=(\d+)/.exec(location.hash);
      const byNumber = m ? D.modes.find((x) => x.index === +m[1] && x.view >= 0) : null;
      const first = D.modes.find((x) => x.kind === "oscillation" && x.view >= 0);
      select(byNumber ? byNumber.view : first ? first.view : 0);
      player.setTime(0.0);
      const pa = view.probe();
      player.setTime(0.25);
      const pb = view.probe();
      document.body.setAttribute("data-view-pixels", `${pa.join(",")};${pb.join(",")}`);
    }
  }

  // --- the table
  app.append(el("h2", { id: "modes" }, "Modes"));
  app.append(el("p", { class: "hint" }, "Name: the body and direction with the largest share of the mode's kinetic energy (translations along and rotations about world axes, the elastic part of a modal body, named by what its dominant FE mode does: bending, torsion or stretch, the axis, and the section holding most of its strain energy); shares of kinetic energy per body and of strain energy per force element, largest first."));
  const zeta = (m) => (m.kind === "unstable" ? `UNSTABLE (doubles in ${fmt(m.doubling_time_s)} s)` : m.damping_ratio);
  const rowsOf = (ms) => ms.map((m) => [m.index, m.undamped_hz, m.damped_hz, zeta(m), m.name,
    m.name_share > 0 ? `${(100 * m.name_share).toFixed(0)} %` : "",
    m.bodies.slice(0, 3).map((b) => `${b.name} ${(100 * b.share).toFixed(0)} %`).join(", "),
    m.elements.slice(0, 2).map((b) => `${b.name} ${(100 * b.share).toFixed(0)} %`).join(", ")]);
  const head = ["mode", "undamped [Hz]", "damped [Hz]", "ζ", "dominant motion", "share", "bodies (kinetic)", "elements (strain)"];
  const clickable = (t, ms) => [...t.querySelectorAll("tr")].slice(1).forEach((tr, i) => {
    const k = ms[i].view;
    if (ms[i].kind === "unstable") tr.setAttribute("class", "failed");
    if (k >= 0 && view) {
      tr.style.cursor = "pointer";
      tr.addEventListener("click", () => { select(k); host.scrollIntoView(); });
    }
  });
  // Zero roots apart: free motions without restoring force, whose ζ is round-off.
  if (zero.length) {
    const zt = table(["mode", "|λ| / 2π [Hz]", "motion"], zero.map((m) => [m.index, m.undamped_hz.toExponential(1), m.name]));
    app.append(el("details", { id: "zero-roots" }, el("summary", {}, `${zero.length} zero roots (below 1e-3 Hz): motions without restoring force (lateral position, heading, travel), not vibrations`), zt));
  }
  const shown = D.modes.filter((m) => m.kind !== "zero");
  const tab = table(head, rowsOf(shown));
  tab.id = "mode-table";
  clickable(tab, shown);
  app.append(tab);
  document.body.setAttribute("data-ready", "1");
})();
