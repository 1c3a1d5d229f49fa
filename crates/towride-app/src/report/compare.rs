//! Comparing runs (`towride compare DIR DIR...`): the channels the runs' `outputs.csv`
//! share, overlaid in one PNG and one self-contained HTML page, with each run's max, min
//! and |peak| against the first run's (like with like) and the RMS of their difference.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::figure::{render, Figure, Panel, Style, Trace};
use crate::scene::channels;
use crate::Error;
use towride_mbs::input::csv_table;

/// Version of the comparison document. 2: the signed `peak`, `reference_peak` and
/// `peak_difference` are gone for max, min and |peak| of each run and their differences.
pub const SCHEMA_VERSION: u32 = 2;

/// One run's outputs as written by `run`.
#[derive(Clone, Debug)]
pub struct Run {
    /// The folder's name (the legend label).
    pub label: String,
    /// Sample times [s].
    pub times: Vec<f64>,
    /// (name, unit, samples) per channel.
    pub channels: Vec<(String, String, Vec<f64>)>,
    /// Its convergence verdict (`run --check`, in its summary.json) per judged channel:
    /// (name, converged); `None` when the run was not checked.
    pub verdict: Option<Vec<(String, bool)>>,
}

impl Run {
    /// The verdict on `channel`: `None` when not checked or not judged.
    fn converged(&self, channel: &str) -> Option<bool> {
        let v = self.verdict.as_ref()?;
        v.iter().find(|(n, _)| n == channel).map(|(_, ok)| *ok)
    }
}

/// The convergence verdict in `dir/summary.json`, if it has one.
fn verdict(dir: &Path) -> Option<Vec<(String, bool)>> {
    let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let channels = v.get("convergence")?.get("channels")?.as_object()?;
    Some(
        channels
            .iter()
            .map(|(n, c)| (n.clone(), c["converged"].as_bool().unwrap_or(false)))
            .collect(),
    )
}

fn bad(file: &Path, line: Option<usize>, field: &str, message: String) -> Error {
    csv_table::error(file, line, field, message).into()
}

/// Reads `dir/outputs.csv` (headers `name [unit]`, the first column time).
pub fn load(dir: &Path) -> Result<Run, Error> {
    let file = dir.join("outputs.csv");
    let mut r = csv::Reader::from_path(&file).map_err(|e| bad(&file, None, "", e.to_string()))?;
    let headers = r
        .headers()
        .map_err(|e| bad(&file, Some(1), "", e.to_string()))?
        .clone();
    let mut names = Vec::new();
    for h in headers.iter() {
        let (name, unit) = h
            .rsplit_once(" [")
            .and_then(|(n, u)| Some((n, u.strip_suffix(']')?)))
            .ok_or_else(|| bad(&file, Some(1), h, "header is not 'name [unit]'".into()))?;
        names.push((name.to_string(), unit.to_string()));
    }
    if names.first().map(|n| n.0.as_str()) != Some("time") {
        return Err(bad(
            &file,
            Some(1),
            "",
            "the first column is not time".into(),
        ));
    }
    let mut cols = vec![Vec::new(); names.len()];
    for (k, rec) in r.records().enumerate() {
        let rec = rec.map_err(|e| bad(&file, Some(k + 2), "", e.to_string()))?;
        for (c, v) in rec.iter().enumerate() {
            let x: f64 = v.trim().parse().map_err(|_| {
                bad(
                    &file,
                    Some(k + 2),
                    &names[c.min(names.len() - 1)].0,
                    format!("'{v}' is not a number"),
                )
            })?;
            cols[c].push(x);
        }
    }
    let times = std::mem::take(&mut cols[0]);
    let channels = names
        .into_iter()
        .zip(cols)
        .skip(1)
        .map(|((n, u), v)| (n, u, v))
        .collect();
    let label = dir.file_name().map_or_else(
        || dir.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    Ok(Run {
        label,
        times,
        channels,
        verdict: verdict(dir),
    })
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

/// The comparison: what `compare` prints with `--json`.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// Layout version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// The run folders, the first the reference.
    pub runs: Vec<String>,
    /// Channels every run has, in the first run's order.
    pub channels: Vec<String>,
    /// Per channel, each later run against the first.
    pub differences: Vec<Difference>,
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

/// Compares `runs` (at least two) channel by channel against the first.
pub fn compare(runs: &[Run]) -> Comparison {
    let first = &runs[0];
    let common: Vec<&(String, String, Vec<f64>)> = first
        .channels
        .iter()
        .filter(|c| {
            runs[1..]
                .iter()
                .all(|r| r.channels.iter().any(|d| d.0 == c.0))
        })
        .collect();
    let mut differences = Vec::new();
    for (name, unit, reference) in &common {
        for r in &runs[1..] {
            let (_, _, v) = r.channels.iter().find(|d| &d.0 == name).expect("common");
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
                rms_difference: if n > 0 {
                    (sum / n as f64).sqrt()
                } else {
                    f64::NAN
                },
                converged: match (first.converged(name), r.converged(name)) {
                    (Some(false), _) | (_, Some(false)) => Some(false),
                    (Some(true), Some(true)) => Some(true),
                    _ => None,
                },
            });
        }
    }
    Comparison {
        schema_version: SCHEMA_VERSION,
        runs: runs.iter().map(|r| r.label.clone()).collect(),
        channels: common.iter().map(|c| c.0.clone()).collect(),
        differences,
        files: Vec::new(),
    }
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

/// Writes `compare.png` (or `.svg` by `format`) and `compare.html` into `out`.
pub fn write(runs: &[Run], c: &mut Comparison, out: &Path, format: &str) -> Result<(), Error> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
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
                    Trace::new(
                        r.label.clone(),
                        r.times.iter().copied().zip(v.iter().copied()).collect(),
                        Style::nth(i),
                    )
                })
                .collect();
            Panel {
                traces,
                ..Panel::new(name.as_str(), "time [s]", format!("{name} [{unit}]"))
            }
        })
        .collect();
    let png = out.join(format!("compare.{format}"));
    let mut fig = Figure::new(panels, 1);
    fig.panel_height = 420;
    render(&png, &fig)?;
    let html = out.join("compare.html");
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
        for (name, unit, v) in &r.channels {
            if !c.channels.contains(name) {
                continue;
            }
            if !first {
                d.push(',');
            }
            first = false;
            super::html::string(&mut d, name);
            d.push_str(":{\"unit\":");
            super::html::string(&mut d, unit);
            d.push_str(",\"v\":");
            super::html::quantised(&mut d, v.iter().copied());
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
        include_str!("assets/compare.js"),
    );
    h
}
