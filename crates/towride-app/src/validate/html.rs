//! The self-contained HTML report of a validated run (`OUT/<run>/report.html`, beside
//! its PNG page): the run's figures, the error metrics per channel and comparison,
//! measured and simulated curves overlaid per sensor (uncorrected and corrected, the
//! time cursor shared), and their Welch spectra. Built from the run report's pieces
//! ([`crate::report::html`]: uPlot, shared script, styles, the quantised signals).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::pipeline::{Comparison, RunValidation};
use super::ValidateError;
use crate::report::figure::{Rgb, MEASURED, SIMULATED};
use crate::report::html::{quantised, string};
use crate::signal::psd::{segment_length, welch};

/// Longest Welch segment [samples] (as the run report's).
const PSD_MAX_SEGMENT: usize = 2048;

fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// A number for JSON: `null` when not finite.
fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        "null".into()
    }
}

fn json<T: serde::Serialize>(out: &mut String, v: &T) {
    out.push_str(
        &serde_json::to_string(v)
            .unwrap_or_else(|_| "null".into())
            .replace("</", "<\\/"),
    );
}

/// A comparison's curves: time from the obstacle [ms], then per channel the measured
/// and simulated samples and the figures.
fn comparison(d: &mut String, c: &Comparison) {
    d.push_str("{\"label\":");
    string(d, c.label);
    let _ = write!(
        d,
        ",\"speed_kmh\":{},\"shift_ms\":{},\"mean_rating\":{},\"t\":",
        num(c.speed_mps * 3.6),
        num(c.shift_s * 1e3),
        num(c.mean_rating)
    );
    quantised(d, c.time_s.iter().map(|t| (t - c.obstacle_time_s) * 1e3));
    d.push_str(",\"channels\":[");
    for (k, f) in c.channels.iter().enumerate() {
        if k > 0 {
            d.push(',');
        }
        d.push_str("{\"figures\":");
        json(d, f);
        for (key, map) in [("measured", &c.measured), ("simulated", &c.simulated)] {
            let _ = write!(d, ",\"{key}\":");
            match map.get(&f.channel) {
                Some(v) => quantised(d, v.iter().copied()),
                None => d.push_str("null"),
            }
        }
        d.push('}');
    }
    d.push_str("]}");
}

/// Welch spectra of the measured and simulated curves of the primary comparison, on
/// one frequency grid.
fn spectra(d: &mut String, c: &Comparison) {
    let n = c.time_s.len();
    let fs = if n > 1 {
        (n - 1) as f64 / (c.time_s[n - 1] - c.time_s[0])
    } else {
        0.0
    };
    let len = segment_length(n, PSD_MAX_SEGMENT);
    let mut freq: Option<Vec<f64>> = None;
    let mut per = String::from("[");
    for (k, f) in c.channels.iter().enumerate() {
        if k > 0 {
            per.push(',');
        }
        per.push('{');
        for (j, (key, map)) in [("measured", &c.measured), ("simulated", &c.simulated)]
            .into_iter()
            .enumerate()
        {
            if j > 0 {
                per.push(',');
            }
            let _ = write!(per, "\"{key}\":");
            let p = map
                .get(&f.channel)
                .filter(|_| fs > 0.0)
                .and_then(|v| welch(v, fs, len));
            match p {
                Some(p) => {
                    json(&mut per, &p.density);
                    freq.get_or_insert(p.freq);
                }
                None => per.push_str("null"),
            }
        }
        per.push('}');
    }
    per.push(']');
    let _ = write!(d, "{{\"segment\":{len},\"fs\":{},\"f\":", num(fs));
    json(d, &freq.unwrap_or_default());
    d.push_str(",\"channels\":");
    d.push_str(&per);
    d.push('}');
}

/// The page of run `run`.
pub fn page(run: &RunValidation) -> String {
    let mut d = String::from("{\"header\":");
    let header: Vec<(String, String)> = super::report::header(run)
        .into_iter()
        .map(|(t, c)| (t, hex(c)))
        .collect();
    json(&mut d, &header);
    d.push_str(",\"colours\":");
    json(&mut d, &[hex(MEASURED), hex(SIMULATED)]);
    let _ = write!(d, ",\"synthetic\":{},\"comparisons\":[", run.synthetic);
    comparison(&mut d, &run.uncorrected);
    if let Some(c) = &run.corrected {
        d.push(',');
        comparison(&mut d, c);
    }
    d.push_str("],\"channels\":");
    json(&mut d, &run.channels);
    d.push_str(",\"psd\":");
    spectra(&mut d, run.primary());
    d.push('}');
    crate::report::html::page(
        &format!("towride validate: {}", run.name),
        &format!("Validation: {}", run.name),
        &d,
        include_str!("../report/assets/validate.js"),
    )
}

/// Writes `dir/report.html` whole or not at all; returns its path.
pub fn write(run: &RunValidation, dir: &Path) -> Result<PathBuf, ValidateError> {
    let io = |path: &Path, source| ValidateError::Io {
        path: path.to_path_buf(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let path = dir.join("report.html");
    crate::atomic::write(&path, page(run)).map_err(|e| io(&path, e))?;
    Ok(path)
}
