//! What a calibration leaves behind and the helpers its driver needs: the `auto`
//! candidates, the Latin hypercube, the ratings, the overlays, and the files
//! (`overrides.toml`, the report PNGs and page).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::params::{number, ParamSpec};
use super::target::Target;
use super::{Calibration, Overlay, Rated};
use crate::report::lineplot::{line_panels, Line, LinePanel};
use crate::study::sensitivity::params::{driven_by_factors, every_value, factor_limits, Base};
use crate::validate::RunValidation;
use towride_mbs::input::Loader;

/// `auto` bounds: an assumed value between half and twice its file value (class values
/// of the `simple` defaults and the vehicle files spread about that much).
const AUTO_FACTOR: f64 = 2.0;
/// Obstacle dimensions `auto` considers (in a road file's obstacles).
const OBSTACLE_KEYS: [&str; 3] = ["height_m", "chord_m", "length_m"];
/// Values that set a stiffness without saying so in their name: an air spring's rate
/// follows from its volume and effective area (`vehicle::air`).
const RATE_KEYS: [&str; 2] = ["volume_m3", "effective_area_m2"];

/// A value's name and a text about it (why it was left out).
pub type Named = (String, String);

/// The scene's assumed (or untagged) stiffness, damping and mass values and its
/// obstacles' dimensions, each within [1/2, 2] of its file value; and the ones the
/// model refuses to take from outside (a value derived from another, as a `simple`
/// vehicle's tyre data), with the reason.
pub fn auto_candidates(scene: &Path) -> Result<(Vec<ParamSpec>, Vec<Named>), crate::Error> {
    let mut out = Vec::new();
    let all = every_value(scene)?;
    for p in &all {
        let Base::Scalar(x) = p.base else { continue };
        // A ring tyre's coupled values are fitted through its independent factors.
        if x <= 0.0 || driven_by_factors(p, &all) {
            continue;
        }
        let key = p.path.rsplit('.').next().unwrap_or(&p.path);
        let obstacle = p.group == "road" && OBSTACLE_KEYS.contains(&key);
        if p.kind == "value" && !obstacle && !RATE_KEYS.contains(&key) {
            continue;
        }
        // A factor's bounds keep inside its open range: the margin to each end halves at
        // most, as the ratio AUTO_FACTOR allows for an unbounded value.
        let [lo, hi] = factor_limits(p, 1.0 / AUTO_FACTOR)
            .map_or([1.0 / AUTO_FACTOR, AUTO_FACTOR], |[l, h]| {
                [l.max(1.0 / AUTO_FACTOR), h.min(AUTO_FACTOR)]
            });
        let Ok(spec) = ParamSpec::new(p, x * lo, x * hi) else {
            continue;
        };
        if obstacle || matches!(spec.class.as_str(), "assumed" | "untagged") {
            out.push(spec);
        }
    }
    // Each candidate set to its own value must still build the scene.
    use rayon::prelude::*;
    let refused: Vec<Option<String>> = out
        .par_iter()
        .map(|s| {
            let loader = Loader::with_overrides(vec![s.override_for(s.file_value)]);
            crate::scene::load_with(scene, &crate::scene::Changes::default(), &loader)
                .err()
                .map(|e| e.to_string())
        })
        .collect();
    let mut kept = Vec::new();
    let mut left = Vec::new();
    for (s, r) in out.into_iter().zip(refused) {
        match r {
            None => kept.push(s),
            Some(why) => left.push((s.name, format!("not settable: {why}"))),
        }
    }
    Ok((kept, left))
}

/// `count` points of a Latin hypercube over the bounds (each value's range cut into
/// `count` strata, one point per stratum, strata paired at random; McKay, Beckman and
/// Conover 1979), deterministic for a seed.
pub fn hypercube(specs: &[ParamSpec], count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut noise = crate::validate::synth::Noise::new(seed);
    let mut next = move || noise.uniform();
    let mut points = vec![vec![0.0; specs.len()]; count];
    for (j, s) in specs.iter().enumerate() {
        let mut strata: Vec<usize> = (0..count).collect();
        for i in (1..count).rev() {
            let k = (next() * (i + 1) as f64) as usize;
            strata.swap(i, k.min(i));
        }
        for (p, &k) in points.iter_mut().zip(&strata) {
            // A run's time shift starts at validate's alignment.
            p[j] = match s.shift_of {
                Some(_) => 0.0,
                None => s.value((k as f64 + next()) / count as f64),
            };
        }
    }
    points
}

/// A run's ratings before and after.
pub fn rated(before: &RunValidation, after: &RunValidation) -> Rated {
    let ratios = |v: &RunValidation| {
        v.primary()
            .channels
            .iter()
            .map(|c| {
                (
                    c.channel.clone(),
                    c.peak_measured_mps2 / c.peak_simulated_mps2,
                )
            })
            .collect()
    };
    Rated {
        name: after.name.clone(),
        descriptor: after.descriptor.clone(),
        before: before.primary().mean_rating,
        after: after.primary().mean_rating,
        peak_ratio_before: ratios(before),
        peak_ratio_after: ratios(after),
    }
}

/// Measured, start and fitted curves of every target (a failed simulation leaves its
/// curve empty).
pub fn overlays(targets: &[Target], loaders: &[Loader; 2], shifts: &[f64]) -> Vec<Overlay> {
    targets
        .iter()
        .enumerate()
        .map(|(k, t)| {
            // Features alone fit no shift: the curves are aligned as the residual aligns them.
            let dt = shifts.get(k).copied().unwrap_or(0.0);
            let sim = |l: &Loader| {
                t.simulate(l, dt)
                    .map(|y| t.thinned(&t.aligned(y)))
                    .unwrap_or_default()
            };
            Overlay {
                run: t.name.clone(),
                channels: t.channels.iter().map(|c| c.name.clone()).collect(),
                time_s: t.time_s.clone(),
                measured: t.measured.clone(),
                start: sim(&loaders[0]),
                fitted: sim(&loaders[1]),
            }
        })
        .collect()
}

/// The override file: one `"FILE:PATH" = VALUE` line per fitted value, tagged
/// `measured` with the runs, the interval and the file value it replaces.
pub fn overrides_toml(cal: &Calibration, producer: &str) -> String {
    let runs: Vec<&str> = cal.targets.iter().map(|t| t.name.as_str()).collect();
    let mut s = format!(
        "# Values fitted by {producer} to the recorded runs {}.\n\
         # `--overrides overrides.toml` applies them to any command; each value's 95 %\n\
         # interval comes from the final sensitivities and residual (docs/calibration.md).\n",
        runs.join(", ")
    );
    for f in &cal.fitted {
        let _ = writeln!(
            s,
            "\"{}:{}\" = {}  # [measured] fitted by towride calibrate on {}; 95 % interval {:.4e}..{:.4e}; file value {} [{}]",
            f.spec.file,
            f.spec.path,
            number(f.value),
            runs.join(", "),
            f.interval[0],
            f.interval[1],
            number(f.spec.file_value),
            f.spec.class
        );
    }
    for (name, reason) in &cal.left {
        let _ = writeln!(s, "# left at its file value: {name}: {reason}");
    }
    s
}

/// Writes `overrides.toml`, `report.png` (cost and overlays) and `report.html` into
/// `dir`; returns the files.
pub fn write(cal: &Calibration, dir: &Path, producer: &str) -> Result<Vec<PathBuf>, crate::Error> {
    std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
    let ov = dir.join("overrides.toml");
    crate::atomic::write(&ov, overrides_toml(cal, producer))
        .map_err(|e| crate::Error::io(&ov, e))?;
    let png = dir.join("report.png");
    let mut panels = vec![cost_panel(cal)];
    for o in &cal.overlays {
        for (c, name) in o.channels.iter().enumerate() {
            let line = |label: &str, y: &[f64]| Line {
                label: label.into(),
                points: o.time_s.iter().copied().zip(y.iter().copied()).collect(),
            };
            let mut lines = vec![line("measured", &o.measured[c])];
            if let Some(y) = o.start.get(c) {
                lines.push(line("file values", y));
            }
            if let Some(y) = o.fitted.get(c) {
                lines.push(line("fitted", y));
            }
            panels.push(LinePanel {
                title: format!("{}: {name}", o.run),
                x_label: "time [s]".into(),
                y_label: "acceleration [m/s^2]".into(),
                lines,
            });
        }
    }
    line_panels(&png, &panels, 2)?;
    let html = dir.join("report.html");
    crate::atomic::write(&html, page(cal, producer)).map_err(|e| crate::Error::io(&html, e))?;
    Ok(vec![ov, png, html])
}

fn cost_panel(cal: &Calibration) -> LinePanel {
    let lines = cal
        .local_fits
        .iter()
        .enumerate()
        .map(|(i, f)| Line {
            label: format!("fit {} (RMS of the normalised residual)", i + 1),
            points: f
                .cost_history
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    let m = cal.targets.iter().map(Target::len).sum::<usize>().max(1);
                    ((k + 1) as f64, (2.0 * c / m as f64).sqrt())
                })
                .collect(),
        })
        .collect();
    LinePanel {
        title: "cost per evaluation (1 = down to the noise)".into(),
        x_label: "evaluation".into(),
        y_label: "residual RMS [noise]".into(),
        lines,
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn page(cal: &Calibration, producer: &str) -> String {
    let mut h = String::from(
        "<!doctype html><meta charset=utf-8><title>towride calibration</title>\
         <style>body{font:14px sans-serif;margin:2em;max-width:1200px}table{border-collapse:collapse;margin:1em 0}\
         td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}td:first-child{text-align:left}\
         .warn{color:#a00}</style><h1>Calibration</h1>",
    );
    let _ = write!(
        h,
        "<p>{} | {} runs fitted, {} held out | {} simulations ({} failed, penalised) | {:.1} s</p>",
        esc(producer),
        cal.targets.len(),
        cal.holdout_runs.len(),
        cal.simulations,
        cal.failed_simulations,
        cal.wall_s
    );
    let _ = write!(
        h,
        "<p>Residual RMS in noise units: {:.2} with the files' values, {:.2} fitted (1 would be a fit down to the sensor and road noise). Collinearity index of the fitted set {:.1} (Brun et al. 2001: beyond 10-15 poorly identifiable).</p>",
        cal.rms_start, cal.rms_fitted, cal.collinearity_index
    );
    h.push_str("<h2>Fitted values</h2><table><tr><th>value</th><th>file value</th><th>source</th><th>bounds</th><th>fitted</th><th>95 % interval</th><th>change</th></tr>");
    for f in &cal.fitted {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{:.4e}</td><td>{}</td><td>{:.3e}..{:.3e}</td><td>{:.4e}{}</td><td>{:.4e}..{:.4e}</td><td>{:+.1} %</td></tr>",
            esc(&f.spec.name),
            f.spec.file_value,
            esc(&f.spec.class),
            f.spec.lo,
            f.spec.hi,
            f.value,
            if f.at_bound { " (at bound)" } else { "" },
            f.interval[0],
            f.interval[1],
            (f.value / f.spec.file_value - 1.0) * 100.0
        );
    }
    h.push_str("</table>");
    if !cal.left.is_empty() {
        h.push_str("<h2>Left at their file values</h2><table><tr><th>value</th><th>why</th></tr>");
        for (n, r) in &cal.left {
            let _ = write!(
                h,
                "<tr><td>{}</td><td style=text-align:left>{}</td></tr>",
                esc(n),
                esc(r)
            );
        }
        h.push_str("</table>");
    }
    h.push_str("<h2>Correlations of the fitted values</h2><table><tr><th></th>");
    for k in 0..cal.fitted.len() {
        let _ = write!(h, "<th>{}</th>", k + 1);
    }
    h.push_str("</tr>");
    for (i, row) in cal.correlation.iter().enumerate() {
        let _ = write!(
            h,
            "<tr><td>{} {}</td>",
            i + 1,
            esc(&cal.fitted[i].spec.name)
        );
        for (k, v) in row.iter().enumerate() {
            let bg = if k != i && v.abs() > super::identify::MAX_CORRELATION {
                " style=background:#fcc"
            } else {
                ""
            };
            let _ = write!(h, "<td{bg}>{v:+.2}</td>");
        }
        h.push_str("</tr>");
    }
    h.push_str("</table><h2>Ratings (validate's mean rating)</h2><table><tr><th>run</th><th>role</th><th>files' values</th><th>fitted</th></tr>");
    for (role, runs) in [
        ("fitted", &cal.fitted_runs),
        ("held out", &cal.holdout_runs),
    ] {
        for r in runs {
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{role}</td><td>{:.3}</td><td>{:.3}</td></tr>",
                esc(&r.name),
                r.before,
                r.after
            );
        }
    }
    h.push_str("</table>");
    if !cal.warnings.is_empty() {
        h.push_str("<h2>Warnings</h2><ul>");
        for w in &cal.warnings {
            let _ = write!(h, "<li class=warn>{}</li>", esc(w));
        }
        h.push_str("</ul>");
    }
    h.push_str("<h2>Cost and overlays</h2><img src=report.png style=max-width:100%>");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every value's range holds exactly one point per stratum (the hypercube's
    /// definition), in the bounded coordinate.
    #[test]
    fn hypercube_puts_one_point_in_each_stratum() {
        let spec = |lo: f64, hi: f64| ParamSpec {
            name: "f:x".into(),
            file: "f".into(),
            path: "x".into(),
            lo,
            hi,
            log: lo > 0.0,
            file_value: lo,
            class: "assumed".into(),
            source: String::new(),
            shift_of: None,
        };
        let specs = [spec(1.0, 100.0), spec(-2.0, 2.0), spec(0.1, 0.2)];
        let n = 11;
        let pts = hypercube(&specs, n, 5);
        assert_eq!(pts.len(), n);
        for (j, s) in specs.iter().enumerate() {
            let mut hit = vec![0; n];
            for p in &pts {
                let u = s.coordinate(p[j]);
                hit[((u * n as f64) as usize).min(n - 1)] += 1;
            }
            assert!(hit.iter().all(|&h| h == 1), "value {j}: {hit:?}");
        }
        // Another seed pairs the strata differently.
        assert_ne!(hypercube(&specs, n, 6), pts);
    }
}
