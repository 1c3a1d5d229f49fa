//! The page of a sweep (`sweep` and `sweep merge` write it beside the summary CSV): a
//! table of the cases with their figures, each case linked to its own report when the
//! sweep kept histories (`cases/<case id>/report.html`), and each figure plotted against
//! a swept parameter, one curve per combination of the others (the hitch force's |peak|
//! against the crossbeam variant, one curve per speed). The HTML page is interactive (uPlot, the
//! parameter on the x axis chosen on the page); the PNG beside it shows the key figures
//! through [`crate::report::figure`]. Both are made from the summary CSV alone, so a merged
//! table of shards gets the same page as an unsharded run.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::report::figure::{render, Figure, Panel, Style, Trace, PALETTE};
use crate::report::html::string;
use crate::scene::channels;
use crate::sweep::cases::{case_dir, cases_dir};
use crate::Error;
use towride_mbs::input::csv_table;

/// The files [`write`] made.
#[derive(Clone, Debug)]
pub struct Files {
    /// The HTML page.
    pub html: PathBuf,
    /// The figure of the key outputs.
    pub png: PathBuf,
}

/// One case of the table.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Case number.
    pub case: usize,
    /// Parameter values as written in the table.
    pub values: Vec<String>,
    /// "completed", "failed" or "interrupted".
    pub status: String,
    /// The figures, in [`Table::figures`] order (`None`: empty cell).
    pub figures: Vec<Option<f64>>,
    /// Why the case failed.
    pub error: String,
    /// The case's report relative to the page, when its folder was kept.
    pub link: Option<String>,
}

/// A sweep summary as read back from its CSV.
#[derive(Clone, Debug, Serialize)]
pub struct Table {
    /// The swept parameters' names.
    pub parameters: Vec<String>,
    /// The figures' names with their units (`hitch_fx abs_peak [N]`).
    pub figures: Vec<String>,
    /// The cases.
    pub rows: Vec<Row>,
}

fn bad(file: &Path, line: Option<usize>, field: &str, message: String) -> Error {
    csv_table::error(file, line, field, message).into()
}

/// Reads a summary CSV (`case`, parameters, `status`, `wall_time [s]`, figures,
/// `error`) and finds the case folders beside it.
pub fn read(csv: &Path) -> Result<Table, Error> {
    let mut r = csv::Reader::from_path(csv).map_err(|e| bad(csv, None, "", e.to_string()))?;
    let h: Vec<String> = r
        .headers()
        .map_err(|e| bad(csv, Some(1), "", e.to_string()))?
        .iter()
        .map(String::from)
        .collect();
    let status = h.iter().position(|c| c == "status");
    let (Some(status), Some("case"), Some("error")) = (
        status,
        h.first().map(String::as_str),
        h.last().map(String::as_str),
    ) else {
        return Err(bad(
            csv,
            Some(1),
            "",
            "not a sweep summary (wants case, parameters, status, wall_time, figures, error)"
                .into(),
        ));
    };
    if h.len() < status + 3 {
        return Err(bad(csv, Some(1), "", "no wall_time column".into()));
    }
    let parameters = h[1..status].to_vec();
    let figures = h[status + 2..h.len() - 1].to_vec();
    let cases = cases_dir(csv.parent().unwrap_or(Path::new(".")));
    let mut rows = Vec::new();
    for (k, rec) in r.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| bad(csv, Some(line), "", e.to_string()))?;
        let get = |c: usize| rec.get(c).unwrap_or("").to_string();
        let case: usize = get(0)
            .parse()
            .map_err(|_| bad(csv, Some(line), "case", "not a case number".into()))?;
        let mut figs = Vec::new();
        for (f, name) in figures.iter().enumerate() {
            let cell = get(status + 2 + f);
            figs.push(if cell.is_empty() {
                None
            } else {
                Some(
                    cell.parse().map_err(|_| {
                        bad(csv, Some(line), name, format!("'{cell}' is not a number"))
                    })?,
                )
            });
        }
        let link = case_dir(&cases, case)
            .join("report.html")
            .is_file()
            .then(|| format!("cases/{}/report.html", crate::sweep::cases::case_id(case)));
        rows.push(Row {
            case,
            values: (1..status).map(get).collect(),
            status: get(status),
            figures: figs,
            error: get(h.len() - 1),
            link,
        });
    }
    Ok(Table {
        parameters,
        figures,
        rows,
    })
}

/// The page's name for summary `csv`: `summary*.csv` gives `report*.html` (shards keep
/// their suffix), any other `NAME.csv` gives `NAME_report.html`.
pub fn page_path(csv: &Path, ext: &str) -> PathBuf {
    let stem = csv.file_stem().unwrap_or_default().to_string_lossy();
    let name = match stem.strip_prefix("summary") {
        Some(rest) => format!("report{rest}.{ext}"),
        None => format!("{stem}_report.{ext}"),
    };
    csv.with_file_name(name)
}

/// A parameter's values as numbers, when they all are.
fn numeric(t: &Table, p: usize) -> Option<Vec<f64>> {
    t.rows.iter().map(|r| r.values[p].parse().ok()).collect()
}

/// The parameter on the x axis: the first that varies and is numeric, else the first
/// that varies.
pub fn x_parameter(t: &Table) -> Option<usize> {
    let varies = |p: usize| t.rows.iter().any(|r| r.values[p] != t.rows[0].values[p]);
    let v: Vec<usize> = (0..t.parameters.len()).filter(|&p| varies(p)).collect();
    v.iter()
        .copied()
        .find(|&p| numeric(t, p).is_some())
        .or(v.first().copied())
}

/// The figures the PNG shows: of a vehicle sweep the hitch force's |peak| (fore-aft and
/// vertical), the trailer's and the hitch sensor's |peak| as the instrument saw them
/// (band-limited, else raw), the crossbeam's largest deflection and strain energy; else
/// the first four that differ between cases (run wall time aside).
pub fn key_figures(t: &Table) -> Vec<usize> {
    let find = |k: &str| t.figures.iter().position(|f| f == k);
    // A band-limited sensor figure by its twin's suffix (`acc_hitch_z_lp100 abs_peak`).
    let sensor = |name: &str, unit: &str| {
        let band = t.figures.iter().position(|f| {
            f.strip_prefix(name)
                .and_then(|r| r.strip_prefix("_lp"))
                .is_some_and(|r| r.ends_with(&format!(" abs_peak [{unit}]")))
        });
        band.or_else(|| find(&format!("{name} abs_peak [{unit}]")))
    };
    let some: Vec<usize> = [
        find(&format!("{} abs_peak [N]", channels::HITCH_FX)),
        find(&format!("{} abs_peak [N]", channels::HITCH_FZ)),
        sensor(channels::TRAILER_AX, "m/s^2"),
        sensor(&channels::acc("hitch", "z"), "m/s^2"),
        find(super::exec::CROSSBEAM_DEFLECTION),
        find(super::exec::CROSSBEAM_ENERGY),
    ]
    .into_iter()
    .flatten()
    .collect();
    if !some.is_empty() {
        return some;
    }
    let varies = |f: usize| {
        let v: Vec<f64> = t.rows.iter().filter_map(|r| r.figures[f]).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(*x), b.max(*x))
            });
        hi - lo > 1e-9 * hi.abs().max(lo.abs())
    };
    (0..t.figures.len())
        .filter(|&f| t.figures[f] != "run wall time [s]" && varies(f))
        .take(4)
        .collect()
}

/// Curves of figure `f` against parameter `x`: one per combination of the other
/// parameters' values (in order of first appearance), points of completed cases sorted
/// by x. A non-numeric parameter is placed by the order of its values.
pub fn curves(t: &Table, x: usize, f: usize) -> Vec<(String, Vec<(f64, f64)>)> {
    let xs: Vec<f64> = numeric(t, x).unwrap_or_else(|| {
        let mut seen: Vec<&str> = Vec::new();
        t.rows
            .iter()
            .map(|r| {
                let v = r.values[x].as_str();
                if !seen.contains(&v) {
                    seen.push(v);
                }
                seen.iter().position(|s| *s == v).unwrap_or(0) as f64
            })
            .collect()
    });
    let mut out: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (r, xv) in t.rows.iter().zip(xs) {
        let label = t
            .parameters
            .iter()
            .zip(&r.values)
            .enumerate()
            .filter(|(p, _)| *p != x)
            .map(|(_, (n, v))| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ");
        let k = match out.iter().position(|(l, _)| *l == label) {
            Some(k) => k,
            None => {
                out.push((label, Vec::new()));
                out.len() - 1
            }
        };
        if let (Some(y), "completed") = (r.figures[f], r.status.as_str()) {
            out[k].1.push((xv, y));
        }
    }
    for (_, p) in &mut out {
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

/// The PNG (or SVG by `png`'s extension): each key figure against the x parameter.
pub fn figure(t: &Table, title: &str, png: &Path) -> Result<(), Error> {
    let Some(x) = x_parameter(t) else {
        // One case (or none varies): nothing to plot against; the table says it all.
        let fig = Figure {
            header: vec![crate::report::figure::HeaderLine {
                text: format!("{title}: no swept parameter varies"),
                size: 24.0,
                colour: [0, 0, 0],
            }],
            ..Figure::new(Vec::new(), 1)
        };
        render(png, &fig)?;
        return Ok(());
    };
    let xlabel = if numeric(t, x).is_some() {
        t.parameters[x].clone()
    } else {
        format!("{} (value number, in sweep order)", t.parameters[x])
    };
    let panels: Vec<Panel> = key_figures(t)
        .into_iter()
        .map(|f| {
            let name = &t.figures[f];
            let traces = curves(t, x, f)
                .into_iter()
                .enumerate()
                .map(|(i, (label, pts))| {
                    let label = if label.is_empty() {
                        name.clone()
                    } else {
                        label
                    };
                    Trace::new(label, pts, Style::line_dots(PALETTE[i % PALETTE.len()]))
                })
                .collect();
            let short = name.rsplit_once(" [").map_or(name.as_str(), |(n, _)| n);
            Panel {
                traces,
                ..Panel::new(
                    format!("{short} against {}", t.parameters[x]),
                    &xlabel,
                    name,
                )
            }
        })
        .collect();
    let cols = if panels.len() > 1 { 2 } else { 1 };
    let mut fig = Figure::new(panels, cols);
    fig.panel_height = 520;
    fig.header = vec![crate::report::figure::HeaderLine {
        text: format!("{title}: {} cases", t.rows.len()),
        size: 28.0,
        colour: [0, 0, 0],
    }];
    render(png, &fig)?;
    Ok(())
}

/// The HTML page of table `t`, with the study's sections in `extra` (`usage`,
/// `robustness`; JSON null: none).
pub fn page(t: &Table, title: &str, png: Option<&str>, extra: &serde_json::Value) -> String {
    let mut d = String::from("{\"title\":");
    string(&mut d, title);
    d.push_str(",\"x\":");
    let _ = write!(d, "{}", x_parameter(t).map_or(-1, |x| x as i64));
    d.push_str(",\"numeric\":");
    let num: Vec<bool> = (0..t.parameters.len())
        .map(|p| numeric(t, p).is_some())
        .collect();
    d.push_str(&serde_json::to_string(&num).unwrap_or_default());
    d.push_str(",\"png\":");
    match png {
        Some(p) => string(&mut d, p),
        None => d.push_str("null"),
    }
    d.push_str(",\"table\":");
    d.push_str(
        &serde_json::to_string(t)
            .unwrap_or_default()
            .replace("</", "<\\/"),
    );
    d.push_str(",\"extra\":");
    d.push_str(&extra.to_string().replace("</", "<\\/"));
    d.push('}');
    // The study's sections (usage, robustness) after the table's own.
    let script = concat!(
        include_str!("../report/assets/sweep.js"),
        include_str!("../report/assets/sweep_study.js")
    );
    crate::report::html::page(
        &format!("towride sweep: {title}"),
        &format!("Sweep: {title}"),
        &d,
        script,
    )
}

/// Writes the page and figure of summary `csv` beside it ([`page_path`]), each whole or
/// not at all.
pub fn write(csv: &Path, title: &str) -> Result<Files, Error> {
    write_with(csv, title, &serde_json::Value::Null)
}

/// [`write`] with the study's sections `extra` (see [`page`]).
pub fn write_with(csv: &Path, title: &str, extra: &serde_json::Value) -> Result<Files, Error> {
    let t = read(csv)?;
    let png = page_path(csv, "png");
    let html = page_path(csv, "html");
    // Rendered under a temporary name, then renamed: whole or not at all.
    let part = png.with_extension("part.png");
    figure(&t, title, &part)?;
    std::fs::rename(&part, &png).map_err(|e| Error::io(&png, e))?;
    let name = png.file_name().map(|n| n.to_string_lossy().into_owned());
    crate::atomic::write(&html, page(&t, title, name.as_deref(), extra))
        .map_err(|e| Error::io(&html, e))?;
    Ok(Files { html, png })
}
