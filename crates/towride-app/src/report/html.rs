//! The self-contained HTML report of a run (`report.html` beside the CSV): interactive
//! time histories grouped like the PNG page plus one chart per unit for the other
//! channels, Welch spectra of every channel, the run summary and the solver's step size
//! and order over time. uPlot (vendored, `vendor/README.md`) and the data are embedded:
//! the file opens from the file system without a network.

use std::fmt::Write as _;

use serde::Serialize;

use super::display::{display_unit, figure_unit};
use super::families::families;
use super::run::run_panels;
use crate::scene::channels;
use crate::signal::psd::{segment_length, welch};
use towride_mbs::model::run::Samples;

pub(crate) const UPLOT_JS: &str = include_str!("vendor/uplot/uPlot.iife.min.js");
pub(crate) const UPLOT_CSS: &str = include_str!("vendor/uplot/uPlot.min.css");
/// DOM helpers, formats and uPlot plugins shared by the pages.
pub(crate) const COMMON_JS: &str = include_str!("assets/common.js");
const REPORT_JS: &str = include_str!("assets/report.js");
/// three.js (vendored, `vendor/README.md`) and the 3D view built on it.
pub(crate) const THREE_JS: &str = include_str!("vendor/three/three.min.js");
pub(crate) const VIEW_JS: &str = include_str!("assets/view3d.js");
pub(crate) const REPORT_CSS: &str = include_str!("assets/report.css");
/// Records uncaught errors on `<html data-errors>` (the browser test reads them).
pub(crate) const ERROR_HOOK: &str = "<script>window.onerror = (m, f, l) => { const b = document.documentElement; \
    b.setAttribute(\"data-errors\", (b.getAttribute(\"data-errors\") || \"\") + m + \" (line \" + l + \"); \"); };</script>";

/// `s` with `&`, `<` and `>` escaped for HTML text.
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// three.js and the 3D view's script, when the page has a view.
pub(crate) fn view_scripts(view: bool) -> String {
    if view {
        format!("<script>{THREE_JS}</script>\n<script>{VIEW_JS}</script>\n")
    } else {
        String::new()
    }
}

/// Longest Welch segment [samples]: 0.5 Hz resolution at 1 kHz sampling.
const PSD_MAX_SEGMENT: usize = 2048;

/// A number for the embedded data: six significant digits, `null` when not finite.
fn num(out: &mut String, v: f64) {
    if !v.is_finite() {
        out.push_str("null");
    } else if v == 0.0 {
        out.push('0');
    } else {
        let s = format!("{v:.5e}");
        let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let mant = if mant.contains('.') {
            mant.trim_end_matches('0').trim_end_matches('.')
        } else {
            mant
        };
        if exp == "0" {
            out.push_str(mant);
        } else {
            let _ = write!(out, "{mant}e{exp}");
        }
    }
}

fn array(out: &mut String, values: impl IntoIterator<Item = f64>) {
    out.push('[');
    for (k, v) in values.into_iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        num(out, v);
    }
    out.push(']');
}

/// A signal as integers and a scale (`{"s":scale,"q":[...]}`, value = q s): a millionth
/// of the signal's largest magnitude, finer than any chart shows or the read-out's five
/// digits near the peak; integers keep the file small and quick to write.
pub(crate) fn quantised(out: &mut String, values: impl Iterator<Item = f64> + Clone) {
    let peak = values
        .clone()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = if peak > 0.0 { peak / 999_999.0 } else { 1.0 };
    // The scale exactly (shortest round-trip form): six digits would put up to 5e-6 of
    // the peak into every value q s.
    let _ = write!(out, "{{\"s\":{scale:e}");
    out.push_str(",\"q\":[");
    for (k, v) in values.enumerate() {
        if k > 0 {
            out.push(',');
        }
        if v.is_finite() {
            integer(out, (v / scale).round() as i64);
        } else {
            out.push_str("null");
        }
    }
    out.push_str("]}");
}

/// `v` in decimal: the bulk of a report's bytes, written without the formatting
/// machinery.
pub(crate) fn integer(out: &mut String, v: i64) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    let mut u = v.unsigned_abs();
    loop {
        i -= 1;
        buf[i] = b'0' + (u % 10) as u8;
        u /= 10;
        if u == 0 {
            break;
        }
    }
    if v < 0 {
        out.push('-');
    }
    out.push_str(std::str::from_utf8(&buf[i..]).unwrap_or("0"));
}

pub(crate) fn string(out: &mut String, s: &str) {
    // serde_json escapes quotes and control characters; `</` is split so that no
    // string can close the script element.
    out.push_str(
        &serde_json::to_string(s)
            .unwrap_or_default()
            .replace("</", "<\\/"),
    );
}

/// One series of a chart: channel index, colour, whether it is drawn dashed (the
/// right side of a left/right pair) and shown at first (the other channel of a
/// raw/band-limited pair is in the legend, hidden).
#[derive(Serialize)]
struct Series {
    ch: usize,
    colour: String,
    width: u32,
    dash: bool,
    show: bool,
}

/// The other channel of a raw/band-limited pair: a band-limited twin's raw channel, a
/// raw channel's twin ([`crate::job::band`]).
fn counterpart(res: &Samples, c: usize) -> Option<usize> {
    let name = &res.channels[c].name;
    if channels::is_band_limited(name) {
        let (raw, _) = name.rsplit_once("_lp")?;
        res.channels.iter().position(|ch| ch.name == raw)
    } else {
        super::run::band_twin(res, name).map(|t| t.0)
    }
}

/// A chart of time histories.
#[derive(Serialize)]
struct Group {
    title: String,
    y: String,
    series: Vec<Series>,
}

/// The charts: the run page's panels, then the remaining channels by family and unit.
fn groups(res: &Samples) -> Vec<Group> {
    let index = |name: &str| res.channels.iter().position(|c| c.name == name);
    let hex = |c: [u8; 3]| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
    let mut used = vec![false; res.channels.len()];
    let mut out: Vec<Group> = Vec::new();
    for p in run_panels(res) {
        let mut series = Vec::new();
        for t in &p.traces {
            let Some(ch) = index(&t.label) else {
                continue;
            };
            // The hidden one of a pair thin, to tell the two apart when both are shown.
            let s = |ch: usize, show: bool| Series {
                ch,
                colour: hex(t.style.colour),
                width: if show { t.style.width.max(1) } else { 1 },
                dash: t.style.width == 1,
                show,
            };
            used[ch] = true;
            series.push(s(ch, true));
            if let Some(other) = counterpart(res, ch) {
                used[other] = true;
                series.push(s(other, false));
            }
        }
        out.push(Group {
            title: p.title,
            y: p.y.label,
            series,
        });
    }
    let palette = super::figure::PALETTE;
    // The twins go with their raw channels, not in families of their own.
    let twin = |c: usize| {
        channels::is_band_limited(&res.channels[c].name) && counterpart(res, c).is_some()
    };
    for f in families(res, |c| !used[c] && !twin(c)) {
        let mut series: Vec<Series> = Vec::new();
        for (k, &c) in f.members.iter().enumerate() {
            let s = |ch: usize, show: bool| Series {
                ch,
                colour: hex(palette[k % palette.len()]),
                width: if show { 2 } else { 1 },
                dash: k >= palette.len(),
                show,
            };
            // The one shown first: a sensor's twin, a force's or deflection's raw channel.
            match counterpart(res, c) {
                Some(t)
                    if channels::band(&res.channels[c].name) == Some(channels::Band::Sensor) =>
                {
                    series.push(s(t, true));
                    series.push(s(c, false));
                }
                Some(t) => {
                    series.push(s(c, true));
                    series.push(s(t, false));
                }
                None => series.push(s(c, true)),
            }
        }
        out.push(Group {
            title: f.title,
            y: f.axis,
            series,
        });
    }
    out
}

/// The report page of a run: `summary_json` is the run summary as written to
/// `summary.json`; `steps` the solver's accepted steps (end time [s], step [s], order);
/// `view` the 3D view's data ([`super::scene3d::run_view`]), if any.
pub fn run_report(
    title: &str,
    res: &Samples,
    summary_json: &str,
    steps: &[(f64, f64, usize)],
    view: Option<&str>,
) -> String {
    let n = res.times.len();
    let fs = if n > 1 {
        (n - 1) as f64 / (res.times[n - 1] - res.times[0])
    } else {
        0.0
    };
    let mut d = String::with_capacity(12 * n * (res.channels.len() + 1) + 4096);
    d.push_str("{\"t\":");
    quantised(&mut d, res.times.iter().copied());
    d.push_str(",\"channels\":[");
    for (c, ch) in res.channels.iter().enumerate() {
        if c > 0 {
            d.push(',');
        }
        d.push_str("{\"name\":");
        string(&mut d, &ch.name);
        d.push_str(",\"unit\":");
        string(&mut d, ch.unit);
        // The charts' values and unit: angles in degrees, units in display form
        // ([`figure_unit`]); `unit` stays the CSV's.
        let (f, shown) = figure_unit(ch.unit);
        d.push_str(",\"du\":");
        string(&mut d, &shown);
        d.push_str(",\"v\":");
        quantised(&mut d, res.rows.iter().map(|r| r[c] * f));
        d.push('}');
    }
    // Each unit's display form for the tables of SI values (the summary's units).
    d.push_str("],\"units\":{");
    let mut seen: Vec<&str> = Vec::new();
    for ch in &res.channels {
        if !seen.contains(&ch.unit) {
            if !seen.is_empty() {
                d.push(',');
            }
            seen.push(ch.unit);
            string(&mut d, ch.unit);
            d.push(':');
            string(&mut d, &display_unit(ch.unit));
        }
    }
    d.push_str("},\"groups\":");
    d.push_str(
        &serde_json::to_string(&groups(res))
            .unwrap_or_default()
            .replace("</", "<\\/"),
    );
    // Spectra of every channel on one frequency grid.
    let len = segment_length(n, PSD_MAX_SEGMENT);
    d.push_str(",\"psd\":{\"segment\":");
    let _ = write!(d, "{len},\"fs\":");
    num(&mut d, fs);
    let mut freq = None;
    d.push_str(",\"density\":[");
    for c in 0..res.channels.len() {
        if c > 0 {
            d.push(',');
        }
        // In the charts' unit, as the histories.
        let f = figure_unit(res.channels[c].unit).0;
        let y: Vec<f64> = res.rows.iter().map(|r| r[c] * f).collect();
        match (fs > 0.0).then(|| welch(&y, fs, len)).flatten() {
            Some(p) => {
                array(&mut d, p.density.iter().copied());
                freq.get_or_insert(p.freq);
            }
            None => d.push_str("null"),
        }
    }
    d.push_str("],\"f\":");
    array(&mut d, freq.unwrap_or_default());
    d.push_str("},\"steps\":{\"t\":");
    array(&mut d, steps.iter().map(|s| s.0));
    d.push_str(",\"h\":");
    array(&mut d, steps.iter().map(|s| s.1));
    d.push_str(",\"order\":");
    array(&mut d, steps.iter().map(|s| s.2 as f64));
    d.push_str("},\"summary\":");
    d.push_str(&summary_json.replace("</", "<\\/"));
    if let Some(v) = view {
        d.push_str(",\"view\":");
        d.push_str(v);
    }
    d.push('}');

    let mut h = String::with_capacity(d.len() + UPLOT_JS.len() + 16384);
    let esc = escape(title);
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"generator\" content=\"towride {}\">\
         <title>towride: {esc}</title>\n<style>{UPLOT_CSS}\n{REPORT_CSS}</style></head>\n\
         <body>\n<h1>{esc}</h1>\n<div id=\"app\"><noscript>This report needs JavaScript \
         (no network: everything is in this file).</noscript></div>\n\
         <script type=\"application/json\" id=\"data\">{d}</script>\n\
         {ERROR_HOOK}\n\
         <script>{UPLOT_JS}</script>\n{three}<script>{COMMON_JS}</script>\n<script>{REPORT_JS}</script>\n</body></html>\n",
        env!("CARGO_PKG_VERSION"),
        three = view_scripts(view.is_some()),
    );
    h
}

/// A self-contained page (the sweep's, a validated run's): `title` and `heading` as
/// text, `data` (JSON) in `<script id="data">`, uPlot, the shared script and the page's
/// own `script`, which builds the page into `#app`.
pub(crate) fn page(title: &str, heading: &str, data: &str, script: &str) -> String {
    let mut h = String::with_capacity(data.len() + UPLOT_JS.len() + script.len() + 8192);
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"generator\" content=\"towride {}\">\
         <title>{}</title>\n<style>{UPLOT_CSS}\n{REPORT_CSS}</style></head>\n\
         <body>\n<h1>{}</h1>\n<div id=\"app\"><noscript>This page needs JavaScript \
         (no network: everything is in this file).</noscript></div>\n\
         <script type=\"application/json\" id=\"data\">{data}</script>\n{ERROR_HOOK}\n\
         <script>{UPLOT_JS}</script>\n<script>{COMMON_JS}</script>\n<script>{script}</script>\n\
         </body></html>\n",
        env!("CARGO_PKG_VERSION"),
        escape(title),
        escape(heading),
    );
    h
}
