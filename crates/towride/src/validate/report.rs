//! Pictures of a validated run: per channel an overlay (measured vs simulated,
//! uncorrected left, corrected right) and a one-page report with the run's figures on
//! top and every channel's two overlays below; for a batch, an HTML index of the pages.

use super::ValidateError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::report::lineplot::{draw_panels, line_panels, Line, LinePanel};
use crate::report::plot::register_font;
use crate::report::ReportError;

use super::pipeline::{Comparison, RunValidation};

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

fn panel(run: &RunValidation, c: &Comparison, i: usize) -> LinePanel {
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
    LinePanel {
        title: format!(
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
        ),
        x_label: "time from obstacle [ms]".into(),
        y_label: format!("{name} [m/s^2]"),
        lines: vec![
            Line {
                label: if run.synthetic {
                    "measured (synthetic)".into()
                } else {
                    "measured".into()
                },
                points: pts(&c.measured[name]),
            },
            Line {
                label: "simulated".into(),
                points: pts(&c.simulated[name]),
            },
        ],
    }
}

fn panels_of(run: &RunValidation, i: usize) -> Vec<LinePanel> {
    let mut v = vec![panel(run, &run.uncorrected, i)];
    if let Some(c) = &run.corrected {
        v.push(panel(run, c, i));
    }
    v
}

/// Writes `dir/<channel>.png` for every channel; returns the files.
pub fn overlays(run: &RunValidation, dir: &Path) -> Result<Vec<PathBuf>, ValidateError> {
    std::fs::create_dir_all(dir).map_err(|e| ValidateError::Io {
        path: dir.to_path_buf(),
        source: e,
    })?;
    let mut files = Vec::new();
    for (i, f) in run.uncorrected.channels.iter().enumerate() {
        let p = dir.join(format!("{}.png", f.channel));
        let panels = panels_of(run, i);
        line_panels(&p, &panels, panels.len())?;
        files.push(p);
    }
    Ok(files)
}

/// The run's figures as lines of text for the page header.
fn header(run: &RunValidation) -> Vec<(String, RGBColor)> {
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
    if !run.notes.is_empty() {
        lines.push((
            format!(
                "{} repair(s) reading the CSV, first: {}",
                run.notes.len(),
                run.notes[0]
            ),
            BLACK,
        ));
    }
    lines
}

/// Writes the one-page report (PNG): figures on top, overlays below.
pub fn page(run: &RunValidation, path: &Path) -> Result<(), ValidateError> {
    register_font();
    let e = |x: &dyn std::fmt::Display| ReportError::Plot(format!("{}: {x}", path.display()));
    let rows = run.uncorrected.channels.len();
    let cols = if run.corrected.is_some() { 2 } else { 1 };
    let head_h = 150;
    let size = (620 * cols as u32, head_h + 300 * rows as u32);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let (top, body) = root.split_vertically(head_h);
    for (k, (text, colour)) in header(run).iter().enumerate() {
        let size = if k == 0 { 24 } else { 17 };
        top.draw(&Text::new(
            text.clone(),
            (16, 12 + 27 * k as i32),
            ("sans-serif", size).into_font().color(colour),
        ))
        .map_err(|x| e(&x))?;
    }
    let panels: Vec<LinePanel> = (0..rows).flat_map(|i| panels_of(run, i)).collect();
    draw_panels(&body, &panels, rows, cols)?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

/// An HTML index of the report pages (relative links), best-rated last.
pub fn index(
    runs: &[(RunValidation, PathBuf)],
    failures: &[(PathBuf, String)],
    path: &Path,
) -> Result<(), ValidateError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut h = String::from("<!doctype html><meta charset=\"utf-8\"><title>towride validate</title>\n<h1>towride validate</h1>\n<table border=1 cellpadding=4><tr><th>run</th><th>synthetic</th><th>rating uncorrected</th><th>rating corrected</th><th>shift [ms]</th></tr>\n");
    let mut sorted: Vec<&(RunValidation, PathBuf)> = runs.iter().collect();
    sorted.sort_by(|a, b| {
        a.0.primary()
            .mean_rating
            .total_cmp(&b.0.primary().mean_rating)
    });
    for (r, page) in &sorted {
        let rel = page.strip_prefix(dir).unwrap_or(page).display().to_string();
        let (rc, sh) = r.corrected.as_ref().map_or(("-".into(), "-".into()), |c| {
            (
                format!("{:.3}", c.mean_rating),
                format!("{:+.1}", c.shift_s * 1e3),
            )
        });
        let _ = writeln!(h, "<tr><td><a href=\"{rel}\">{}</a></td><td>{}</td><td>{:.3}</td><td>{rc}</td><td>{sh}</td></tr>", r.name, r.synthetic, r.uncorrected.mean_rating);
    }
    h.push_str("</table>\n");
    for (f, err) in failures {
        let _ = writeln!(
            h,
            "<p style=\"color:red\">{}: {}</p>",
            f.display(),
            err.replace('<', "&lt;")
        );
    }
    for (r, page) in &sorted {
        let rel = page.strip_prefix(dir).unwrap_or(page).display().to_string();
        let _ = writeln!(
            h,
            "<h2 id=\"{0}\">{0}</h2><img src=\"{rel}\" style=\"max-width:100%\">",
            r.name
        );
    }
    std::fs::write(path, h).map_err(|e| ValidateError::Io {
        path: path.to_path_buf(),
        source: e,
    })
}
