//! Comparing runs (`towride compare DIR DIR...`): the channels the runs' `outputs.csv`
//! share, overlaid in one PNG and one self-contained HTML page, with each run's max, min
//! and |peak| against the first run's (like with like) and the RMS of their difference.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::display;
use super::figure::{render, Figure, Panel, Style, Trace};
use crate::scene::channels;
use crate::Error;
use towride_mbs::input::regular::same_file;

mod basis;
mod load;
mod units;

pub use basis::Basis;
pub use load::load;

/// Version of the comparison document. 2: the signed `peak`, `reference_peak` and
/// `peak_difference` are gone for max, min and |peak| of each run and their differences.
/// 3: `not_comparable` (modal coordinates of different bases) and `conversions`.
pub const SCHEMA_VERSION: u32 = 3;

/// One run's outputs as written by `run`.
#[derive(Clone, Debug)]
pub struct Run {
    /// The folder's name (the legend label).
    pub label: String,
    /// Its `outputs.csv` (for errors).
    pub file: PathBuf,
    /// Sample times [s].
    pub times: Vec<f64>,
    /// (name, unit, samples) per channel.
    pub channels: Vec<(String, String, Vec<f64>)>,
    /// Its convergence verdict (`run --check`, in its summary.json) per judged channel:
    /// (name, converged); `None` when the run was not checked.
    pub verdict: Option<Vec<(String, bool)>>,
    /// The Craig-Bampton basis of each modal body (from summary.json; empty when not
    /// recorded).
    pub bases: Vec<Basis>,
}

impl Run {
    /// The verdict on `channel`: `None` when not checked or not judged.
    fn converged(&self, channel: &str) -> Option<bool> {
        let v = self.verdict.as_ref()?;
        v.iter().find(|(n, _)| n == channel).map(|(_, ok)| *ok)
    }
}

/// One channel of one run against the first run's.
#[derive(Clone, Debug, Serialize)]
pub struct Difference {
    /// Channel.
    pub channel: String,
    /// Its unit.
    pub unit: String,
    /// The run (folder name).
    pub run: String,
    /// The first run's largest value.
    pub reference_max: f64,
    /// The first run's smallest value.
    pub reference_min: f64,
    /// The first run's |peak|, max(|max|, |min|).
    pub reference_abs_peak: f64,
    /// This run's largest value.
    pub max: f64,
    /// This run's smallest value.
    pub min: f64,
    /// This run's |peak|.
    pub abs_peak: f64,
    /// `max - reference_max`.
    pub max_difference: f64,
    /// `min - reference_min` (negative: a deeper minimum).
    pub min_difference: f64,
    /// `abs_peak - reference_abs_peak` (positive: a larger magnitude, whichever side).
    pub abs_peak_difference: f64,
    /// Root mean square of the difference to the first run (linearly interpolated at
    /// this run's samples) where the two overlap in time.
    pub rms_difference: f64,
    /// The convergence verdicts of the two runs (`run --check`) on this channel: false
    /// when either failed it, true when both passed it, `None` otherwise (a run not
    /// checked, or a channel its verdict does not judge).
    pub converged: Option<bool>,
}

/// Modal coordinates of a run that do not compare with the reference's.
#[derive(Clone, Debug, Serialize)]
pub struct NotComparable {
    /// The run (folder name).
    pub run: String,
    /// The modal body.
    pub body: String,
    /// Its modal coordinates in either run (`hitch_eta_1`, ...).
    pub channels: Vec<String>,
    /// `not comparable (different modal bases)`.
    pub reason: String,
    /// The two bases: variant and kept modes.
    pub detail: String,
}

/// A run's channel read in another unit and converted to the reference's.
#[derive(Clone, Debug, Serialize)]
pub struct Conversion {
    /// The run (folder name).
    pub run: String,
    /// Channel.
    pub channel: String,
    /// The unit in the run's file.
    pub from: String,
    /// The reference's unit, the one compared in.
    pub to: String,
    /// The factor applied.
    pub factor: f64,
}

/// The reason given for modal coordinates of different bases.
pub const DIFFERENT_BASES: &str = "not comparable (different modal bases)";

/// The comparison: what `compare` prints with `--json`.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// Layout version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// The run folders, the first the reference.
    pub runs: Vec<String>,
    /// Channels every run has and every run's can be compared with the reference's, in
    /// the first run's order.
    pub channels: Vec<String>,
    /// Per channel, each later run against the first.
    pub differences: Vec<Difference>,
    /// Modal coordinates left out: another modal basis than the reference's.
    pub not_comparable: Vec<NotComparable>,
    /// Channels converted to the reference's unit (another SI prefix).
    pub conversions: Vec<Conversion>,
    /// The files written.
    pub files: Vec<PathBuf>,
}

/// Max, min and |peak| of the finite values of `v` (NaN for none).
fn extremes(v: &[f64]) -> [f64; 3] {
    let (lo, hi) = v
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
    if lo > hi {
        [f64::NAN; 3]
    } else {
        [hi, lo, hi.abs().max(lo.abs())]
    }
}

/// Linear interpolation of (t, y) at `x` (`None` outside).
fn interp(t: &[f64], y: &[f64], x: f64) -> Option<f64> {
    if t.is_empty() || x < t[0] || x > t[t.len() - 1] {
        return None;
    }
    let k = t.partition_point(|&v| v <= x).clamp(1, t.len() - 1);
    let (t0, t1) = (t[k - 1], t[k]);
    if t1 == t0 {
        return Some(y[k]);
    }
    Some(y[k - 1] + (y[k] - y[k - 1]) * (x - t0) / (t1 - t0))
}

/// Modal coordinates of `runs[1..]` that do not compare with `runs[0]`'s.
fn modal_mismatches(runs: &[Run]) -> Vec<NotComparable> {
    let first = &runs[0];
    let mut out = Vec::new();
    for r in &runs[1..] {
        let mut bodies: Vec<&str> = first
            .bases
            .iter()
            .chain(&r.bases)
            .map(|b| b.body.as_str())
            .collect();
        bodies.dedup();
        for body in bodies {
            let Some(detail) = basis::mismatch(body, &first.bases, &r.bases) else {
                continue;
            };
            let owns = |n: &String| n.strip_prefix(body).is_some_and(|x| x.starts_with("_eta_"));
            let mut chans: Vec<String> = first
                .channels
                .iter()
                .map(|c| c.0.clone())
                .filter(owns)
                .collect();
            for c in r.channels.iter().map(|c| &c.0).filter(|n| owns(n)) {
                if !chans.contains(c) {
                    chans.push(c.clone());
                }
            }
            out.push(NotComparable {
                run: r.label.clone(),
                body: body.to_string(),
                channels: chans,
                reason: DIFFERENT_BASES.into(),
                detail: format!("{body}: {detail}"),
            });
        }
    }
    out
}

/// Compares `runs` (at least two) channel by channel against the first, in the first's
/// units (another SI prefix converted). Errors: a run whose times do not overlap the
/// first's, a channel in a unit that does not convert (file and column named).
pub fn compare(runs: &[Run]) -> Result<Comparison, Error> {
    let first = &runs[0];
    let not_comparable = modal_mismatches(runs);
    let left_out = |name: &str| {
        not_comparable
            .iter()
            .any(|n| n.channels.iter().any(|c| c == name))
    };
    // In the reference's column order (a run's CSV has `hitch_eta_2` before
    // `hitch_eta_10` already).
    let common: Vec<&(String, String, Vec<f64>)> = first
        .channels
        .iter()
        .filter(|c| {
            !left_out(&c.0)
                && runs[1..]
                    .iter()
                    .all(|r| r.channels.iter().any(|d| d.0 == c.0))
        })
        .collect();
    let (t0, t1) = (first.times[0], first.times[first.times.len() - 1]);
    // Times in common: at least one sample of each run within the reference's span
    // (else the RMS of the difference is of nothing).
    for r in &runs[1..] {
        if !r.times.iter().any(|t| (t0..=t1).contains(t)) {
            let (a, b) = (r.times[0], r.times[r.times.len() - 1]);
            return Err(load::bad(
                &r.file,
                Some(2),
                "time",
                format!(
                    "no sample of its times ({a} to {b} s) lies within the reference {}'s ({t0} to {t1} s): no time in common to compare",
                    first.label
                ),
            ));
        }
    }
    let mut differences = Vec::new();
    let mut conversions = Vec::new();
    for (name, unit, reference) in &common {
        for r in &runs[1..] {
            let k = r
                .channels
                .iter()
                .position(|d| &d.0 == name)
                .expect("common");
            let (_, run_unit, raw) = &r.channels[k];
            let f = units::factor(run_unit, unit).ok_or_else(|| {
                load::bad(
                    &r.file,
                    Some(1),
                    name,
                    format!(
                        "unit [{run_unit}] does not convert to the reference {}'s [{unit}] (only SI prefixes of one unit are converted)",
                        first.label
                    ),
                )
            })?;
            let scaled: Vec<f64>;
            let v: &[f64] = if f == 1.0 {
                raw
            } else {
                conversions.push(Conversion {
                    run: r.label.clone(),
                    channel: name.clone(),
                    from: run_unit.clone(),
                    to: unit.clone(),
                    factor: f,
                });
                scaled = raw.iter().map(|x| x * f).collect();
                &scaled
            };
            let (mut sum, mut n) = (0.0, 0usize);
            for (t, y) in r.times.iter().zip(v) {
                if let Some(yr) = interp(&first.times, reference, *t) {
                    sum += (y - yr) * (y - yr);
                    n += 1;
                }
            }
            let ([max0, min0, abs0], [max, min, abs]) = (extremes(reference), extremes(v));
            differences.push(Difference {
                channel: name.clone(),
                unit: unit.clone(),
                run: r.label.clone(),
                reference_max: max0,
                reference_min: min0,
                reference_abs_peak: abs0,
                max,
                min,
                abs_peak: abs,
                max_difference: max - max0,
                min_difference: min - min0,
                abs_peak_difference: abs - abs0,
                // n > 0: a sample lies within the reference's span (checked above).
                rms_difference: (sum / n.max(1) as f64).sqrt(),
                converged: match (first.converged(name), r.converged(name)) {
                    (Some(false), _) | (_, Some(false)) => Some(false),
                    (Some(true), Some(true)) => Some(true),
                    _ => None,
                },
            });
        }
    }
    Ok(Comparison {
        schema_version: SCHEMA_VERSION,
        runs: runs.iter().map(|r| r.label.clone()).collect(),
        channels: common.iter().map(|c| c.0.clone()).collect(),
        differences,
        not_comparable,
        conversions,
        files: Vec::new(),
    })
}

/// The channels the PNG overlays: the hitch force and trailer acceleration when the
/// runs are scenes, else the first four.
fn figure_channels(c: &Comparison) -> Vec<String> {
    let key = [
        channels::HITCH_FX.to_string(),
        channels::HITCH_FZ.to_string(),
        channels::TRAILER_AX.to_string(),
        channels::acc("hitch", "z"),
    ];
    let some: Vec<String> = key
        .iter()
        .filter(|k| c.channels.iter().any(|n| n == *k))
        .map(|k| k.to_string())
        .collect();
    if some.is_empty() {
        c.channels.iter().take(4).cloned().collect()
    } else {
        some
    }
}

/// Factor that brings run `r`'s `channel` into the reference's unit.
fn factor(c: &Comparison, r: &Run, channel: &str) -> f64 {
    c.conversions
        .iter()
        .find(|x| x.run == r.label && x.channel == channel)
        .map_or(1.0, |x| x.factor)
}

/// Writes `compare.png` (or `.svg` by `format`) and `compare.html` into `out`; refuses
/// to write over a run's own files (`--out` a run folder holding a link to them).
pub fn write(runs: &[Run], c: &mut Comparison, out: &Path, format: &str) -> Result<(), Error> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let png = out.join(format!("compare.{format}"));
    let html = out.join("compare.html");
    for r in runs {
        let dir = r.file.parent().unwrap_or(Path::new("."));
        for input in [r.file.clone(), dir.join("summary.json")] {
            if let Some(o) = [&png, &html].into_iter().find(|o| same_file(o, &input)) {
                return Err(load::bad(
                    o,
                    None,
                    "",
                    format!("is the input {} (the same file): compare never overwrites its inputs; give another --out", input.display()),
                ));
            }
        }
    }
    let panels: Vec<Panel> = figure_channels(c)
        .iter()
        .map(|name| {
            let unit = &runs[0]
                .channels
                .iter()
                .find(|d| &d.0 == name)
                .expect("common")
                .1;
            let traces = runs
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let v = &r.channels.iter().find(|d| &d.0 == name).expect("common").2;
                    let f = factor(c, r, name);
                    Trace::new(
                        r.label.clone(),
                        r.times
                            .iter()
                            .copied()
                            .zip(v.iter().map(|x| x * f))
                            .collect(),
                        Style::nth(i),
                    )
                })
                .collect();
            Panel {
                traces,
                ..Panel::new(
                    name.as_str(),
                    "time [s]",
                    format!("{name} [{}]", display::display_unit(unit)),
                )
            }
        })
        .collect();
    let mut fig = Figure::new(panels, 1);
    fig.panel_height = 420;
    render(&png, &fig)?;
    std::fs::write(&html, page(runs, c)).map_err(|e| Error::io(&html, e))?;
    c.files = vec![png, html];
    Ok(())
}

/// The HTML page: a channel picker over the runs' overlaid histories (uPlot) and the
/// table of differences.
fn page(runs: &[Run], c: &Comparison) -> String {
    let mut d = String::from("{\"runs\":[");
    for (i, r) in runs.iter().enumerate() {
        if i > 0 {
            d.push(',');
        }
        d.push_str("{\"label\":");
        super::html::string(&mut d, &r.label);
        d.push_str(",\"t\":");
        super::html::quantised(&mut d, r.times.iter().copied());
        d.push_str(",\"channels\":{");
        let mut first = true;
        for (name, _, v) in &r.channels {
            if !c.channels.contains(name) {
                continue;
            }
            // In the reference's unit: the page overlays them on one axis.
            let (unit, f) = (
                &runs[0]
                    .channels
                    .iter()
                    .find(|d| &d.0 == name)
                    .expect("common")
                    .1,
                factor(c, r, name),
            );
            if !first {
                d.push(',');
            }
            first = false;
            super::html::string(&mut d, name);
            // The page only shows the unit: its display form (m/s²).
            d.push_str(":{\"unit\":");
            super::html::string(&mut d, &display::display_unit(unit));
            d.push_str(",\"v\":");
            super::html::quantised(&mut d, v.iter().map(|x| x * f));
            d.push('}');
        }
        d.push_str("}}");
    }
    d.push_str("],\"comparison\":");
    d.push_str(
        &serde_json::to_string(c)
            .unwrap_or_default()
            .replace("</", "<\\/"),
    );
    d.push('}');
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>towride: comparison of {} runs</title>\n<style>{}\n{}</style></head>\n\
         <body>\n<h1>Comparison: {}</h1>\n<div id=\"app\"></div>\n{}\n\
         <script type=\"application/json\" id=\"data\">{d}</script>\n\
         <script>{}</script>\n<script>{}</script>\n<script>{}</script>\n</body></html>\n",
        runs.len(),
        super::html::UPLOT_CSS,
        super::html::REPORT_CSS,
        super::html::escape(&c.runs.join(" · ")),
        super::html::ERROR_HOOK,
        super::html::UPLOT_JS,
        super::html::COMMON_JS,
        include_str!("../assets/compare.js"),
    );
    h
}
