//! A study's files: `sensitivity.csv` (one row per parameter, units in the headers),
//! one `tornado_<output>.png` per output ([`super::tornado`]), `sensitivity.html`
//! ([`super::page`]) and `sensitivity.json`.

use std::path::Path;

use super::{tornado, Method, Study};
use crate::error::{Error, Result};

pub use super::page::page;

/// Writes the study's files into `dir` and records them in `study.written`.
pub fn write(study: &mut Study, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let csv = dir.join("sensitivity.csv");
    write_csv(study, &csv)?;
    // An output without a figure gets no chart; charts of an earlier study's outputs
    // are removed, not left to stand beside this study's page.
    let mut charts = Vec::new();
    for (o, out) in study.outputs.iter().enumerate() {
        let png = tornado::file(dir, &out.name);
        if tornado::tornado(study, o, &png)? {
            charts.push(png);
        }
    }
    tornado::remove_stale(dir, &charts)?;
    let html = dir.join("sensitivity.html");
    crate::atomic::write(&html, page(study)).map_err(|e| Error::io(&html, e))?;
    study.written = std::iter::once(&csv)
        .chain(&charts)
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
