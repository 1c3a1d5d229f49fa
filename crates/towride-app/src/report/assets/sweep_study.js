// towride sweep page, the study's sections (D.extra): damage per km of the [usage]
// spectrum with the spectrum and its source classes, and the ranking's robustness to
// the [robustness] block's values. Placed first: they are the study's answers.
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const X = D.extra || {};
  const app = document.getElementById("app");
  const before = document.getElementById("plots");
  const put = (node) => app.insertBefore(node, before);
  const pct = (v) => `${+(100 * v).toFixed(1)} %`;

  if (X.usage) {
    const S = X.usage.spectrum, K = X.usage.per_km || [];
    put(el("h2", { id: "usage" }, "Damage per kilometre (usage spectrum)"));
    put(el("p", {}, `${fmt(S.obstacles_per_km)} obstacles per km; each passage at one case of the mix below. ` +
      "Damage per km = obstacles per km × Σ share × the case's IIW damage per passage (Miner); km to D = 0.5: the allowable Miner sum for steel (IIW-2259-15) over it."));
    const keys = S.mix.length ? S.mix[0].values.map((kv) => kv[0]) : [];
    put(table(keys.concat(["share"]), S.mix.map((m) => m.values.map((kv) => kv[1].replace(/"/g, "")).concat([pct(m.share)]))));
    if (S.provenance.length)
      put(el("p", { class: "hint" }, "Source of the spectrum: ", ...S.provenance.map((p) =>
        el("span", {}, el("b", {}, `${p.key} [${p.class}]`), ` ${p.source}. `))));
    else
      put(el("p", { class: "failed" }, "The spectrum's values carry no source class."));
    // One row per group (the crossbeam variant), per stress point its km to D = 0.5.
    const point = (f) => f.replace(/^hitch_stress_/, "").replace(/ IIW damage per passage \[-\]$/, "");
    const points = [...new Set(K.map((k) => k.figure))];
    // A group by its values; the header names the parameters.
    const gname = (k) => k.group.map((x) => x[1]).join(", ");
    const groups = [...new Set(K.map(gname))];
    const cell = (g, f) => K.find((k) => k.figure === f && gname(k) === g);
    const best = points.map((f) => Math.min(...K.filter((k) => k.figure === f && k.damage_per_km != null).map((k) => k.damage_per_km)));
    const head = [K.length ? K[0].group.map((x) => x[0]).join(", ") : "group"].concat(points.flatMap((f) => [`${point(f)}: damage per km [1/km]`, `${point(f)}: km to D = 0.5 [km]`]));
    const tb = el("table", { id: "usage-table" }, el("tr", {}, ...head.map((h) => el("th", {}, h))));
    for (const g of groups) {
      const row = el("tr", {}, el("td", {}, g));
      points.forEach((f, i) => {
        const c = cell(g, f);
        const d = c && c.damage_per_km, km = c && c.km_to_allowable;
        const mark = d != null && d === best[i] ? { style: "font-weight:bold" } : {};
        row.append(el("td", mark, d == null ? "no result" : fmt(d)), el("td", mark, km == null ? "–" : fmt(km)));
      });
      tb.append(row);
    }
    put(el("div", { style: "overflow-x:auto" }, tb));
    put(el("p", { class: "hint" }, "Bold: the group with the least damage per km at that point."));
  }

  const R = X.robustness;
  if (R) {
    const B = R.block;
    put(el("h2", { id: "robustness" }, "Robustness of the ranking"));
    const sub = B.subset.length ? B.subset.map(([k, v]) => `${k} in {${v.join(", ")}}`).join(", ") : "the whole grid";
    put(el("p", { class: R.status === "completed" ? "" : "failed" }, `Status: ${R.status}.` + (R.note ? ` ${R.note}` : "")));
    put(el("p", {}, `${B.by} ranked by each figure's mean over ${sub} (${R.cases_per_run} cases per run), ` +
      `nominal against each value below at each end of its range: ${R.perturbations.length} perturbed runs of that grid (${fmt(R.wall_s)} s of wall time in the sweep that ran them; a resumed sweep counts only its own).`));
    put(table(["moved value", "class", "from", "file value", "scale factors [low, high]"],
      B.moves.map((m) => [m.parameter, m.class, m.from, m.base, `${fmt(m.factors[0])}, ${fmt(m.factors[1])}`])));
    const figs = R.nominal ? R.nominal.figures.map((f) => f.figure) : [];
    // Short labels keep the table on the page; the full names are in the tooltips.
    const fshort = (f) => f.replace(/^hitch_stress_/, "").replace(/^hitch_bracket_/, "bracket ").replace(/ per passage \[-\]$/, "");
    const pshort = (p) => p.split(/[:/]/).slice(-1)[0];
    if (figs.length && R.perturbations.length) {
      const tb = el("table", { id: "robustness-table" },
        el("tr", {}, el("th", {}, "perturbation"), ...figs.map((f) => el("th", { title: f }, fshort(f)))),
        el("tr", {}, el("td", {}, "nominal best"), ...R.nominal.figures.map((f) => el("td", {}, el("b", {}, `${B.by} ${f.best}`)))));
      for (const p of R.perturbations) {
        const row = el("tr", {}, el("td", { title: p.parameter }, `${pshort(p.parameter)} × ${fmt(p.factor)}` + (p.failed ? `, ${p.failed} failed` : "")));
        for (const f of figs) {
          const o = p.outcomes.find((q) => q.figure === f);
          if (!o) { row.append(el("td", {}, p.note || "–")); continue; }
          // Green: the nominal best stays best; amber: within the best's spread; red: neither.
          const bg = o.stays_best ? "#d8f0d8" : o.within_spread ? "#f8e8c0" : "#f4c8c8";
          const said = o.stays_best ? "" : ` (nominal best ${o.nominal_best}: rank ${o.nominal_best_rank}${o.within_spread ? ", within spread" : ""})`;
          row.append(el("td", { style: `background:${bg}` }, `τ ${o.tau_b == null ? "–" : o.tau_b.toFixed(3)}`, el("br", {}), `best ${o.best}${said}`));
        }
        tb.append(row);
      }
      // The least tau and how often the nominal best held, per figure.
      const worst = figs.map((f) => {
        const os = R.perturbations.map((p) => p.outcomes.find((q) => q.figure === f)).filter((o) => o);
        const taus = os.map((o) => o.tau_b).filter((t) => t != null);
        return [`τ ≥ ${taus.length ? Math.min(...taus).toFixed(3) : "–"}`, `held ${os.filter((o) => o.stays_best).length} of ${os.length}`];
      });
      tb.append(el("tr", {}, el("td", {}, el("b", {}, "over all")), ...worst.map((w) => el("td", {}, el("b", {}, w[0]), el("br", {}), el("b", {}, w[1])))));
      put(el("div", { style: "overflow-x:auto" }, tb));
      put(el("p", { class: "hint" }, "τ: Kendall's tau-b of the perturbed means against the nominal ones (1: the same order, -1: reversed). " +
        "Green: the nominal best stays best; amber: it does not, but its perturbed mean is within the spread the new best shows over the grid (speed and load move the best by more); red: neither."));
    }
  }
})();
