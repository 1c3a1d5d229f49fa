//! The self-contained HTML report of a validated run (`OUT/<run>/report.html`, beside
//! its PNG page): the run's figures, the error metrics per channel and comparison,
//! measured and simulated curves overlaid per sensor (uncorrected and corrected, the
//! time cursor shared), and their spectra ([`super::spectra`]). Built from the run report's pieces
//! ([`crate::report::html`]: uPlot, shared script, styles, the quantised signals).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::pipeline::{Comparison, RunValidation};
use super::spectra;
use super::ValidateError;
use crate::report::figure::{Rgb, MEASURED, SIMULATED};
use crate::report::html::{quantised, string};

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

/// Spectra of the measured and simulated curves of the primary comparison, on one
/// frequency grid up to the band both carry ([`super::spectra`]).
fn spectra(d: &mut String, run: &RunValidation) {
    let c = run.primary();
    let n = c.time_s.len();
    let fs = if n > 1 {
        (n - 1) as f64 / (c.time_s[n - 1] - c.time_s[0])
    } else {
        0.0
    };
    let band = spectra::band_hz(fs, run.simulation_rate_hz, run.acquisition_cutoff_hz);
    let mut grid: Option<spectra::Spectrum> = None;
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
            match map
                .get(&f.channel)
                .and_then(|v| spectra::density(v, fs, band))
            {
                Some(p) => {
                    json(&mut per, &p.density);
                    grid.get_or_insert(p);
                }
                None => per.push_str("null"),
            }
        }
        per.push('}');
    }
    per.push(']');
    let (segment_s, segments, freq) = grid.map_or((f64::NAN, 0, Vec::new()), |g| {
        (g.segment_s, g.segments, g.freq)
    });
    let _ = write!(
        d,
        "{{\"fs\":{},\"band_hz\":{},\"recording_hz\":{},\"simulation_hz\":{},\"cutoff_hz\":{},\"segment_s\":{},\"segments\":{segments},\"f\":",
        num(fs),
        num(band),
        num(run.sample_rate_hz),
        num(run.simulation_rate_hz),
        num(run.acquisition_cutoff_hz),
        num(segment_s)
    );
    json(d, &freq);
    d.push_str(",\"channels\":");
    d.push_str(&per);
    d.push('}');
}

/// Styles of the validation pages beyond the reports' own: wide tables scroll inside
/// their box, never past the page; figures take the content width.
const VALIDATE_CSS: &str = ".wide { overflow-x: auto; max-width: 100%; }\n\
    svg.trend { width: 100%; max-width: 1600px; height: auto; display: block; }\n\
    img.page { max-width: 100%; }\n\
    td.l, th.l { text-align: left; }";

/// A page without script (a folder's index and trends) in the reports' shell: the same
/// head and styles as a run's report and a validated run's page; `body` is HTML.
pub(crate) fn static_page(title: &str, body: &str) -> String {
    use crate::report::html::{escape, REPORT_CSS};
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"generator\" content=\"towride {}\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>{}</title>\n<style>{REPORT_CSS}\n{VALIDATE_CSS}</style></head>\n\
         <body>\n<h1>{}</h1>\n{body}\n</body></html>\n",
        env!("CARGO_PKG_VERSION"),
        escape(title),
        escape(title),
    )
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
    spectra(&mut d, run);
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
