//! A study's files: `sensitivity.csv` (one row per parameter, units in the headers),
//! `tornado.png` (the first output's ranking through [`crate::report::figure`], the
//! colour-blind palette), `sensitivity.html` (offline, the report's style) and
//! `sensitivity.json`.

use std::fmt::Write as _;
use std::path::Path;

use super::{Method, Study};
use crate::error::{Error, Result};
use crate::report::figure::{render, Axis, Figure, HeaderLine, Panel, Style, Trace, PALETTE};
use crate::report::html::escape;

/// Bars in the tornado chart.
const TORNADO_ROWS: usize = 15;

/// Writes the study's files into `dir` and records them in `study.written`.
pub fn write(study: &mut Study, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let csv = dir.join("sensitivity.csv");
    write_csv(study, &csv)?;
    let png = dir.join("tornado.png");
    // No bar to draw (every figure missing): no chart, and an old one is not left to
    // stand beside this study's page.
    let drawn = tornado(study, &png)?;
    if !drawn && png.exists() {
        std::fs::remove_file(&png).map_err(|e| Error::io(&png, e))?;
    }
    let html = dir.join("sensitivity.html");
    crate::atomic::write(&html, page(study)).map_err(|e| Error::io(&html, e))?;
    study.written = [&csv]
        .into_iter()
        .chain(drawn.then_some(&png))
        .chain([&html])
        .map(|p| p.display().to_string())
        .collect();
    let json = dir.join("sensitivity.json");
    study.written.push(json.display().to_string());
    let text = serde_json::to_string_pretty(study).unwrap_or_default();
    crate::atomic::write(&json, text).map_err(|e| Error::io(&json, e))
}

fn write_csv(s: &Study, path: &Path) -> Result<()> {
    let io = |e: csv::Error| Error::io(path, e.into());
    let file = crate::atomic::Atomic::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = csv::Writer::from_writer(file);
    let mut head: Vec<String> = [
        "parameter",
        "group",
        "kind",
        "base value",
        "line",
        "range low [-]",
        "range high [-]",
    ]
    .map(String::from)
    .to_vec();
    for o in &s.outputs {
        match s.method {
            Method::Oat => head.push(format!("{} elasticity [-]", o.name)),
            Method::Morris => {
                head.push(format!("{} mu* [{}]", o.name, o.unit));
                head.push(format!("{} sigma [{}]", o.name, o.unit));
                head.push(format!("{} mu*/base [-]", o.name));
            }
        }
    }
    w.write_record(&head).map_err(io)?;
    for p in &s.params {
        let mut row = vec![
            p.param.name.clone(),
            p.param.group.clone(),
            p.param.kind.clone(),
            format!("{}", p.param.base_value()),
            p.param.line.to_string(),
            format!("{}", p.range[0]),
            format!("{}", p.range[1]),
        ];
        // A figure that could not be computed is an empty cell, never NaN.
        let f = |v: Option<f64>| {
            v.filter(|x| x.is_finite())
                .map_or(String::new(), |x| format!("{x:.6e}"))
        };
        for o in 0..s.outputs.len() {
            match s.method {
                Method::Oat => row.push(f(p.elasticity.get(o).copied().flatten())),
                Method::Morris => {
                    let e = p.morris.get(o);
                    row.push(f(e.map(|e| e.mu_star)));
                    row.push(f(e.map(|e| e.sigma)));
                    row.push(f(p.mu_star_rel.get(o).copied()));
                }
            }
        }
        w.write_record(&row).map_err(io)?;
    }
    let file = w
        .into_inner()
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))?;
    file.commit().map_err(|e| Error::io(path, e))
}

/// The value a parameter is ranked by for output `o`, signed where the method gives a
/// sign (the OAT elasticity; Morris: mu with the sign of mu, mu* as the length).
fn bar(s: &Study, p: &super::ParamResult, o: usize) -> Option<f64> {
    match s.method {
        Method::Oat => p.elasticity.get(o).copied().flatten(),
        Method::Morris => {
            let e = p.morris.get(o)?;
            let r = *p.mu_star_rel.get(o)?;
            r.is_finite().then(|| if e.mu < 0.0 { -r } else { r })
        }
    }
}

/// The tornado chart of the first output: the strongest parameters as horizontal bars,
/// increasing ones in one colour and decreasing ones in another. False (nothing drawn)
/// when no parameter has a figure.
pub fn tornado(s: &Study, path: &Path) -> Result<bool> {
    let Some(out) = s.outputs.first() else {
        return Ok(false);
    };
    let rank: Vec<_> = s
        .ranking(0)
        .into_iter()
        .filter(|p| bar(s, p, 0).is_some())
        .take(TORNADO_ROWS)
        .collect();
    let n = rank.len();
    if n == 0 {
        return Ok(false);
    }
    // A bar too short to see is left out: drawn, its round cap was a blob that looked
    // larger than the bars above it (the table gives the value).
    let longest = rank
        .iter()
        .filter_map(|p| bar(s, p, 0))
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let (mut up, mut down) = (Vec::new(), Vec::new());
    let mut labels = Vec::new();
    for (i, p) in rank.iter().enumerate() {
        let y = (n - i) as f64;
        let v = bar(s, p, 0).unwrap_or(0.0);
        if v.abs() > 0.01 * longest {
            let seg = if v >= 0.0 { &mut up } else { &mut down };
            seg.extend([(0.0, y), (v, y), (f64::NAN, f64::NAN)]);
        }
        labels.push((y, short(&p.param.name)));
    }
    let what = match s.method {
        Method::Oat => "elasticity d ln y / d ln p at +-10 % [-]",
        Method::Morris => "Morris mu* / base output (sign of mu) [-]",
    };
    let mut panel = Panel::new(
        format!("{} [{}]: base {:.4e}", out.name, out.unit, out.base),
        what,
        "",
    );
    panel.y = Axis {
        label: String::new(),
        log: false,
        range: Some((0.3, n as f64 + 0.7)),
        labels,
    };
    let width = (360 / n.max(8)) as u32;
    for (pts, label, c) in [
        (up, "raises the output", PALETTE[1]),
        (down, "lowers the output", PALETTE[0]),
    ] {
        if !pts.is_empty() {
            panel.traces.push(Trace::new(
                label,
                pts,
                Style {
                    colour: c,
                    width,
                    dot: 0.0,
                },
            ));
        }
    }
    let mut fig = Figure::new(vec![panel], 1);
    fig.panel_height = 120 + 40 * n as u32;
    fig.header.push(HeaderLine {
        text: format!(
            "Sensitivity of {} ({}, {} runs): {}",
            out.name, s.method, s.runs, s.file
        ),
        size: 22.0,
        colour: [40, 40, 40],
    });
    if let Some(note) = &s.note {
        fig.header.push(HeaderLine {
            text: note.clone(),
            size: 18.0,
            colour: [180, 30, 30],
        });
    }
    render(path, &fig)?;
    Ok(true)
}

/// `fabia/hitch.toml:bracket_bushing.stiffness_n_m` as `hitch.toml:bracket_bushing.stiffness_n_m`.
fn short(name: &str) -> String {
    match name.split_once(':') {
        Some((f, p)) => format!("{}:{p}", f.rsplit('/').next().unwrap_or(f)),
        None => name.into(),
    }
}

/// A figure's cell: the number, or why there is none ("undefined: base value 0", "-" for
/// a failed or missing run); `sign` "{:+.4}" shows the sign.
fn cell(v: Option<f64>, p: &super::ParamResult, sign: &str) -> String {
    match v.filter(|x| x.is_finite()) {
        Some(x) if sign.is_empty() => format!("{x:.4}"),
        Some(x) => format!("{x:+.4}"),
        None => match &p.note {
            Some(n) => format!("<span title=\"{}\">undefined</span>", escape(n)),
            None => "-".into(),
        },
    }
}

/// The HTML page: settings, the tornado chart and the table of every parameter.
pub fn page(s: &Study) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>towride: sensitivity of {}</title>\
         <style>{}</style></head><body>\n<h1>Sensitivity: {}</h1>\n<p>{}, {} runs on {} threads in {:.1} s ({:.1} s of runs){}</p>\n",
        escape(&s.file),
        crate::report::html::REPORT_CSS,
        escape(&s.file),
        s.method,
        s.runs,
        s.jobs,
        s.wall_s,
        s.runs_wall_s,
        if s.method == Method::Morris {
            format!("; {} trajectories, {} levels, seed {}", s.trajectories, s.levels, s.seed)
        } else {
            "; central differences at 0.9 and 1.1 times each value".into()
        }
    );
    if let Some(note) = &s.note {
        // First, before any figure: the figures below are partial.
        let _ = writeln!(
            h,
            "<p style=\"border:2px solid #b41e1e;background:#fdecea;padding:0.6em;font-weight:bold\">{}</p>",
            escape(note)
        );
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
    h.push_str("<h2>Ranking of the first output</h2>\n");
    if s.ranking(0).iter().any(|p| bar(s, p, 0).is_some()) {
        h.push_str(
            "<p><img src=\"tornado.png\" alt=\"tornado chart\" style=\"max-width:100%\"></p>\n",
        );
    } else {
        h.push_str("<p>No parameter has a figure for this output: no chart.</p>\n");
    }
    h.push_str("<h2>Outputs</h2>\n<table><tr><th>output</th><th>unit</th><th>base run</th></tr>\n");
    for o in &s.outputs {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{:.5e}</td></tr>",
            escape(&o.name),
            escape(&o.unit),
            o.base
        );
    }
    h.push_str("</table>\n<h2>Parameters, ranked by the first output</h2>\n<div style=\"overflow-x:auto\"><table><tr><th>parameter</th><th>group</th><th>kind</th><th>base</th>");
    for o in &s.outputs {
        match s.method {
            Method::Oat => {
                let _ = write!(h, "<th>{} elasticity</th>", escape(&o.name));
            }
            Method::Morris => {
                let _ = write!(
                    h,
                    "<th>{} mu*/base</th><th>sigma/base</th>",
                    escape(&o.name)
                );
            }
        }
    }
    h.push_str("</tr>\n");
    for p in s.ranking(0) {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td style=\"white-space:nowrap\">{:.4e}</td>",
            escape(&p.param.name),
            escape(&p.param.group),
            escape(&p.param.kind),
            p.param.base_value()
        );
        for (o, out) in s.outputs.iter().enumerate() {
            match s.method {
                Method::Oat => {
                    let _ = write!(
                        h,
                        "<td>{}</td>",
                        cell(p.elasticity.get(o).copied().flatten(), p, "{:+.4}")
                    );
                }
                Method::Morris => {
                    let e = &p.morris[o];
                    let defined = p.param.base_value() != 0.0;
                    let rel = |v: f64| Some(v / out.base.abs()).filter(|_| defined);
                    let _ = write!(
                        h,
                        "<td>{}</td><td>{}</td>",
                        cell(rel(e.mu_star), p, ""),
                        cell(rel(e.sigma), p, "")
                    );
                }
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table></div>\n");
    if !s.failed.is_empty() {
        h.push_str("<h2>Failed runs</h2>\n<ul>\n");
        for f in &s.failed {
            let _ = writeln!(h, "<li>{}: {}</li>", escape(&f.changes), escape(&f.error));
        }
        h.push_str("</ul>\n");
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
