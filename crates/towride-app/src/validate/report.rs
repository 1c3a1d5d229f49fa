//! Pictures of a validated run: per channel an overlay (measured vs simulated,
//! uncorrected left, corrected right) and a one-page report with the run's figures on
//! top and every channel's two overlays below; for a batch, an HTML index of the pages.

use super::ValidateError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::report::figure::{
    render, Figure, HeaderLine, Panel, Rgb, Style, Trace, MEASURED, SIMULATED,
};

use super::pipeline::{Comparison, RunValidation};
pub use crate::report::figure::Format;

const BLACK: Rgb = [0, 0, 0];
const RED: Rgb = [190, 0, 0];
const BLUE: Rgb = [0, 80, 160];

/// The grade of a rating, by the thresholds commonly quoted for ISO/TS 18571.
pub fn grade(r: f64) -> &'static str {
    if r > 0.94 {
        "excellent"
    } else if r > 0.8 {
        "good"
    } else if r > 0.58 {
        "fair"
    } else {
        "poor"
    }
}

fn panel(run: &RunValidation, c: &Comparison, i: usize) -> Panel {
    let f = &c.channels[i];
    let name = &f.channel;
    // Time from the obstacle as this comparison places it, in milliseconds.
    let pts = |y: &[f64]| -> Vec<(f64, f64)> {
        c.time_s
            .iter()
            .zip(y)
            .map(|(t, v)| ((t - c.obstacle_time_s) * 1e3, *v))
            .collect()
    };
    let title = format!(
        "{}: R {:.3} {}, {:.2} km/h{}",
        c.label,
        f.rating.overall,
        grade(f.rating.overall),
        c.speed_mps * 3.6,
        if c.label == "corrected" {
            format!(", {:+.1} ms", c.shift_s * 1e3)
        } else {
            String::new()
        }
    );
    let measured = if run.synthetic {
        "measured (synthetic)"
    } else {
        "measured"
    };
    Panel {
        traces: vec![
            Trace::new(measured, pts(&c.measured[name]), Style::line(MEASURED)),
            Trace::new("simulated", pts(&c.simulated[name]), Style::line(SIMULATED)),
        ],
        ..Panel::new(title, "time from obstacle [ms]", format!("{name} [m/s²]"))
    }
}

fn panels_of(run: &RunValidation, i: usize) -> Vec<Panel> {
    let mut v = vec![panel(run, &run.uncorrected, i)];
    if let Some(c) = &run.corrected {
        v.push(panel(run, c, i));
    }
    v
}

/// Writes `dir/<channel>.<format>` for every channel; returns the files.
pub fn overlays(
    run: &RunValidation,
    dir: &Path,
    format: Format,
) -> Result<Vec<PathBuf>, ValidateError> {
    std::fs::create_dir_all(dir).map_err(|e| ValidateError::Io {
        path: dir.to_path_buf(),
        source: e,
    })?;
    let mut files = Vec::new();
    for (i, f) in run.uncorrected.channels.iter().enumerate() {
        let p = format.file(dir, &f.channel);
        let panels = panels_of(run, i);
        let cols = panels.len();
        render(&p, &Figure::new(panels, cols))?;
        files.push(p);
    }
    Ok(files)
}

/// The run's figures as lines of text for the page header.
pub(crate) fn header(run: &RunValidation) -> Vec<(String, Rgb)> {
    let mut lines = Vec::new();
    // An empty load case is the scene's own (a vehicle without a trailer has none).
    let title = if run.load_case.is_empty() {
        format!("{}: {}", run.name, run.obstacle)
    } else {
        format!(
            "{}: {} with trailer {}",
            run.name, run.obstacle, run.load_case
        )
    };
    lines.push((title, BLACK));
    if let Some(g) = &run.obstacle_geometry {
        let n = g.header_lines().len();
        for (k, l) in g.header_lines().into_iter().enumerate() {
            let assumed = k + 1 == n && !g.assumed.is_empty();
            lines.push((l, if assumed { RED } else { BLACK }));
        }
    }
    if run.synthetic {
        lines.push((
            "SYNTHETIC DATA: a simulation passed through a sensor model, not a measurement".into(),
            RED,
        ));
    }
    let v = run.speed.speed_mps;
    let from = match run.speed.source {
        super::speed::SpeedSource::Foils => "the foils",
        super::speed::SpeedSource::Channel => "the speed channel",
        super::speed::SpeedSource::Descriptor => "the descriptor",
    };
    let mut s = format!(
        "speed: nominal {:.2} km/h, from {from} {:.2} km/h ({:+.2} % nominal vs true)",
        run.nominal_speed_mps * 3.6,
        v * 3.6,
        (run.nominal_speed_mps / v - 1.0) * 100.0
    );
    if let (Some(w), Some(l)) = (run.implied_wheelbase_m, run.wheelbase_m) {
        let _ = write!(s, "; implied wheelbase {w:.3} m (model {l:.3} m)");
    }
    for d in &run.speed.channel_dropouts_s {
        let _ = write!(
            s,
            "; speed channel dropout {:.3}-{:.3} s left out",
            d[0], d[1]
        );
    }
    lines.push((s, BLACK));
    let u = run.uncorrected.mean_rating;
    let mut s = format!("mean rating uncorrected {u:.3} ({})", grade(u));
    if let Some(c) = &run.corrected {
        let _ = write!(
            s,
            "   corrected {:.3} ({})   time shift {:+.1} ms{}",
            c.mean_rating,
            grade(c.mean_rating),
            c.shift_s * 1e3,
            if c.shift_at_bound {
                " (AT THE SEARCH BOUND)"
            } else {
                ""
            }
        );
    }
    lines.push((s, BLUE));
    let quiet = &run
        .corrected
        .as_ref()
        .unwrap_or(&run.uncorrected)
        .without_signal;
    if !quiet.is_empty() {
        lines.push((
            format!(
                "left out of the mean rating, no signal above the sensor noise (RMS < {} x the quiet road's): {}",
                super::compare::SIGNAL_MIN,
                quiet.join(", ")
            ),
            BLACK,
        ));
    }
    // Every note, a line each, up to a page's room; the rest are in summary.json.
    const NOTES_SHOWN: usize = 5;
    if !run.notes.is_empty() {
        lines.push((
            format!("{} note(s) reading the run:", run.notes.len()),
            BLACK,
        ));
        for n in run.notes.iter().take(NOTES_SHOWN) {
            lines.push((format!("  {n}"), BLACK));
        }
        if run.notes.len() > NOTES_SHOWN {
            lines.push((
                format!(
                    "  and {} more (summary.json `notes`)",
                    run.notes.len() - NOTES_SHOWN
                ),
                BLACK,
            ));
        }
    }
    lines
}

/// Writes the one-page report (PNG or SVG by extension): figures on top, overlays below.
pub fn page(run: &RunValidation, path: &Path) -> Result<(), ValidateError> {
    let rows = run.uncorrected.channels.len();
    let cols = if run.corrected.is_some() { 2 } else { 1 };
    let mut fig = Figure::new((0..rows).flat_map(|i| panels_of(run, i)).collect(), cols);
    fig.panel_height = 460;
    fig.header = header(run)
        .into_iter()
        .enumerate()
        .map(|(k, (text, colour))| HeaderLine {
            text,
            size: if k == 0 { 30.0 } else { 22.0 },
            colour,
        })
        .collect();
    render(path, &fig)?;
    Ok(())
}

/// An HTML index of the report pages (relative links), worst-rated first, in the
/// reports' page shell ([`super::html::static_page`]).
/// `not_run`: descriptors an interruption kept from being validated, said first.
pub fn index(
    runs: &[(RunValidation, PathBuf)],
    failures: &[(PathBuf, String)],
    not_run: &[PathBuf],
    path: &Path,
) -> Result<(), ValidateError> {
    use crate::report::html::escape;
    let dir = path.parent().unwrap_or(Path::new("."));
    let rel = |p: &Path| escape(&p.strip_prefix(dir).unwrap_or(p).display().to_string());
    let mut h = String::new();
    let mut sorted: Vec<&(RunValidation, PathBuf)> = runs.iter().collect();
    sorted.sort_by(|a, b| {
        a.0.primary()
            .mean_rating
            .total_cmp(&b.0.primary().mean_rating)
    });
    let _ = write!(
        h,
        "<p>{} run(s), worst mean rating first; {} failed. The trends over the folder: <a href=\"trends.html\">trends.html</a>.</p>",
        runs.len(),
        failures.len()
    );
    if !not_run.is_empty() {
        let names: Vec<String> = not_run
            .iter()
            .map(|f| escape(&f.display().to_string()))
            .collect();
        let _ = writeln!(
            h,
            "<p class=\"failed\">Interrupted: {} run(s) not validated: {}.</p>",
            not_run.len(),
            names.join(", ")
        );
    }
    for (f, err) in failures {
        let _ = writeln!(
            h,
            "<p class=\"failed\">{}: {}</p>",
            escape(&f.display().to_string()),
            escape(err)
        );
    }
    h.push_str("<div class=\"wide\"><table><tr><th>run</th><th class=\"l\">obstacle</th><th class=\"l\">load case</th><th>speed [km/h]</th><th>synthetic</th><th>rating uncorrected</th><th>rating corrected</th><th>shift [ms]</th><th>interactive</th></tr>\n");
    for (r, page) in &sorted {
        let (rc, sh) = r.corrected.as_ref().map_or(("–".into(), "–".into()), |c| {
            (
                format!("{:.3} ({})", c.mean_rating, grade(c.mean_rating)),
                format!("{:+.1}", c.shift_s * 1e3),
            )
        });
        // The run's HTML report beside its page, when written.
        let html = page.with_file_name("report.html");
        let link = if html.is_file() {
            format!("<a href=\"{}\">report.html</a>", rel(&html))
        } else {
            String::new()
        };
        let u = r.uncorrected.mean_rating;
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#{0}\">{0}</a></td><td class=\"l\">{1}</td><td class=\"l\">{2}</td><td>{3:.2}</td><td>{4}</td><td>{u:.3} ({5})</td><td>{rc}</td><td>{sh}</td><td>{link}</td></tr>",
            escape(&r.name),
            escape(&r.obstacle),
            escape(&r.load_case),
            r.speed.speed_mps * 3.6,
            if r.synthetic { "yes" } else { "no" },
            grade(u),
        );
    }
    h.push_str("</table></div>\n");
    for (r, page) in &sorted {
        let _ = writeln!(
            h,
            "<h2 id=\"{0}\">{0}</h2><p><a href=\"{1}\">{1}</a></p><img class=\"page\" src=\"{1}\" alt=\"the report page of {0}\">",
            escape(&r.name),
            rel(page)
        );
    }
    crate::atomic::write(path, super::html::static_page("towride validate", &h)).map_err(|e| {
        ValidateError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    })
}
