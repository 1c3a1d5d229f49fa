//! The study's HTML page (offline, the report's style): what was run, a failure banner
//! first, the base run's outputs with their signs, one tornado chart per output and the
//! figures of every parameter in tables that fit a 1300 px window.

use crate::report::display::display_unit;
use std::fmt::Write as _;

use super::numbers::{exact, sig, signed, with_unit};
use super::tornado::{self, bar, short};
use super::{Method, OutputInfo, ParamResult, Study};
use crate::report::html::escape;

/// Output columns per table: eight of them beside the parameter's name fit 1300 px, so
/// a study of many outputs gets several tables instead of one thousands of pixels wide.
pub const COLUMNS: usize = 8;

/// Failed runs listed on the page (all of them are in `sensitivity.json`).
const FAILED_SHOWN: usize = 10;

/// The page's own styles, after the report's.
const CSS: &str = "\
.banner{border:2px solid #b41e1e;background:#fdecea;padding:0.6em;font-weight:bold}\
.tornadoes{display:grid;grid-template-columns:repeat(auto-fill,minmax(560px,1fr));gap:12px 20px}\
figure.tornado{margin:0}figure.tornado img{width:100%}\
figure.tornado figcaption{font-weight:bold;margin:4px 0}\
.wide{overflow-x:auto}\
table.figures th.out{width:88px;max-width:88px;vertical-align:bottom;font-size:12px;font-weight:normal}\
table.figures td.name,table.figures td.base{white-space:nowrap}";

/// An output name with a break opportunity after each `_` of its channel and before
/// its measure (`abs_peak` kept whole): a long name wraps inside a narrow column header
/// instead of widening it.
fn breakable(name: &str) -> String {
    let (channel, measure) = name.rsplit_once('.').unwrap_or((name, ""));
    let channel = escape(channel).replace('_', "_<wbr>");
    if measure.is_empty() {
        channel
    } else {
        format!("{channel}.<wbr>{}", escape(measure))
    }
}

/// The page.
pub fn page(s: &Study) -> String {
    let mut h = String::new();
    let how = match s.method {
        Method::Oat => "elasticities d ln y / d ln p by central differences at 0.9 and 1.1 \
                        times each value"
            .to_string(),
        Method::Morris => format!(
            "mu* and sigma of the elementary effects over each value's range, {} \
             trajectories, {} levels, seed {}",
            s.trajectories, s.levels, s.seed
        ),
    };
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>towride: sensitivity of {file}</title><style>{}{CSS}</style></head><body>\n\
         <h1>Sensitivity: {file}</h1>\n<p><b>{}</b>: {how}; {} runs on {} threads in \
         {:.1} s ({:.1} s of runs).</p>\n",
        crate::report::html::REPORT_CSS,
        s.method,
        s.runs,
        s.jobs,
        s.wall_s,
        s.runs_wall_s,
        file = escape(&s.file),
    );
    // First, before any figure: the figures below are partial, and which runs failed.
    if let Some(note) = &s.note {
        let _ = writeln!(h, "<p class=\"banner\">{}</p>", escape(note));
    }
    if !s.failed.is_empty() {
        h.push_str("<ul class=\"failed-runs\">\n");
        for f in s.failed.iter().take(FAILED_SHOWN) {
            let _ = writeln!(h, "<li>{}: {}</li>", escape(&f.changes), escape(&f.error));
        }
        if s.failed.len() > FAILED_SHOWN {
            let _ = writeln!(
                h,
                "<li>and {} more (every one in sensitivity.json)</li>",
                s.failed.len() - FAILED_SHOWN
            );
        }
        h.push_str("</ul>\n");
    }
    let p = &s.produced_by;
    if !p.towride_version.is_empty() {
        let _ = writeln!(
            h,
            "<p>Produced by towride {} (commit {}): <code>{}</code></p>",
            escape(&p.towride_version),
            escape(&p.git_commit),
            escape(&p.command_line.join(" "))
        );
    }
    if !s.overrides.is_empty() {
        // What every run was changed by (a shortened run is not the scene as filed).
        let _ = writeln!(
            h,
            "<p>Overrides under every run: <code>{}</code></p>",
            escape(&s.overrides.join(", "))
        );
    }
    outputs(&mut h, s);
    charts(&mut h, s);
    match s.method {
        Method::Oat => tables(&mut h, s, "Elasticities d ln y / d ln p [-]", |p, o| {
            p.elasticity.get(o).copied().flatten()
        }),
        Method::Morris => {
            // Relative to the base output, as the charts: comparable across outputs.
            let rel = |p: &ParamResult, o: usize, v: f64| {
                let base = s.outputs.get(o).map_or(f64::NAN, |b| b.base.abs());
                Some(v / base).filter(|x| x.is_finite() && p.param.base_value() != 0.0)
            };
            tables(&mut h, s, "Morris mu* / |base output| [-]", |p, o| {
                p.morris.get(o).and_then(|e| rel(p, o, e.mu_star))
            });
            tables(&mut h, s, "Morris sigma / |base output| [-]", |p, o| {
                p.morris.get(o).and_then(|e| rel(p, o, e.sigma))
            });
        }
    }
    if !s.inactive.is_empty() {
        let _ = writeln!(
            h,
            "<h2>Values the model does not depend on</h2>\n<p>{}</p>",
            escape(&s.inactive.join(", "))
        );
    }
    h.push_str("</body></html>\n");
    h
}

/// The base run's value of an output, signed, with its unit.
pub fn base_value(o: &OutputInfo) -> String {
    with_unit(&sig(o.base, 4), &display_unit(&o.unit))
}

/// The outputs and the base run's value of each; an `.abs_peak` also with the signed
/// sample at its peak, which the magnitude hides.
fn outputs(h: &mut String, s: &Study) {
    h.push_str(
        "<h2>Outputs of the base run</h2>\n<table><tr><th>output</th><th>unit</th>\
         <th>base run</th><th>signed value at the peak</th></tr>\n",
    );
    for o in &s.outputs {
        let at_peak = o.base_signed.map_or(String::new(), |v| {
            with_unit(&sig(v, 4), &display_unit(&o.unit))
        });
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&o.name),
            escape(&display_unit(&o.unit)),
            escape(&base_value(o)),
            escape(&at_peak)
        );
    }
    h.push_str("</table>\n");
}

/// One tornado chart per output, captioned with its name, unit and base value.
fn charts(h: &mut String, s: &Study) {
    let _ = writeln!(
        h,
        "<h2>Ranking of each output</h2>\n<p class=\"hint\">Per output, the {} parameters \
         with the largest {}; bars under 1 % of the longest are left out. The tables below \
         give every parameter.</p>\n<div class=\"tornadoes\">",
        tornado::TORNADO_ROWS,
        tornado::measure(s.method),
    );
    for (o, out) in s.outputs.iter().enumerate() {
        // The picture carries its own title (it is read on its own too); the text
        // alternative repeats it.
        let title = escape(&format!(
            "{}, {}",
            tornado::title(out),
            tornado::base_run(out)
        ));
        let drawn = s.params.iter().any(|p| bar(s, p, o).is_some());
        let body = if drawn {
            let file = tornado::file(std::path::Path::new(""), &out.name);
            format!(
                "<img src=\"{}\" alt=\"tornado chart of {}\">",
                escape(&file.display().to_string()),
                title.replace('"', "&quot;"),
            )
        } else {
            format!(
                "<figcaption>{title}</figcaption><p>No parameter has a figure for this \
                 output: no chart.</p>"
            )
        };
        let _ = writeln!(h, "<figure class=\"tornado\">{body}</figure>");
    }
    h.push_str("</div>\n");
}

/// The figures `value(param, output)` of every parameter, ranked by the first output,
/// in tables of [`COLUMNS`] outputs each.
fn tables(
    h: &mut String,
    s: &Study,
    what: &str,
    value: impl Fn(&ParamResult, usize) -> Option<f64>,
) {
    let ranked = s.ranking(0);
    let n = s.outputs.len();
    let chunks = n.div_ceil(COLUMNS).max(1);
    for c in 0..chunks {
        let cols = c * COLUMNS..((c + 1) * COLUMNS).min(n);
        let part = if chunks > 1 {
            format!(", outputs {} to {} of {n}", cols.start + 1, cols.end)
        } else {
            String::new()
        };
        let _ = write!(
            h,
            "<h2>{}{part}</h2>\n<div class=\"wide\"><table class=\"figures\"><tr>\
             <th>parameter (ranked by the first output)</th><th>kind</th><th>base value</th>",
            escape(what)
        );
        for o in &s.outputs[cols.clone()] {
            let _ = write!(
                h,
                "<th class=\"out\">{} [{}]</th>",
                breakable(&o.name),
                escape(&display_unit(&o.unit))
            );
        }
        h.push_str("</tr>\n");
        // Shading by magnitude within the table guides the eye to the large figures.
        let largest = ranked
            .iter()
            .flat_map(|p| cols.clone().filter_map(|o| value(p, o)))
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for p in &ranked {
            let _ = write!(
                h,
                "<tr><td class=\"name\" title=\"{} (group {})\">{}</td><td>{}</td>\
                 <td class=\"base\">{}</td>",
                escape(&p.param.name),
                escape(&p.param.group),
                escape(&short(&p.param.name)),
                escape(&p.param.kind),
                exact(p.param.base_value())
            );
            for o in cols.clone() {
                h.push_str(&cell(value(p, o), p, largest, s.method == Method::Oat));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</table></div>\n");
    }
}

/// A figure's cell: the number to two significant figures (signed where the sign is
/// the figure's meaning), shaded by its size; or why there is none.
fn cell(v: Option<f64>, p: &ParamResult, largest: f64, with_sign: bool) -> String {
    match v.filter(|x| x.is_finite()) {
        Some(x) => {
            let alpha = if largest > 0.0 {
                0.45 * x.abs() / largest
            } else {
                0.0
            };
            // The charts' colours: orange raises the output, blue lowers it.
            let rgb = if x >= 0.0 { "213,94,0" } else { "0,114,178" };
            let text = if with_sign { signed(x, 2) } else { sig(x, 2) };
            format!("<td style=\"background:rgba({rgb},{alpha:.2})\">{text}</td>")
        }
        None => match &p.note {
            Some(n) => format!("<td><span title=\"{}\">undefined</span></td>", escape(n)),
            None => "<td title=\"a run failed or was not run\">-</td>".into(),
        },
    }
}
