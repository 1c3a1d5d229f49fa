//! A run's files, written from its data: `outputs.csv`, `plots.png` (scenes) and
//! `plots_outputs.png` (scenes with `[[output]]` tables),
//! `report.html` (with the 3D view when the run recorded poses) and `summary.json`. The
//! run pipeline returns a [`RunResult`] and never writes; this printer does (as
//! ripgrep's searcher hands matches to a printer).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use crate::atomic::{self, Atomic};
use crate::error::{Error, Result};
use crate::job::RunResult;
use towride_mbs::model::run::Samples;
use towride_mbs::model::System;

/// Writes the samples as CSV with units in the headers, whole or not at all
/// ([`crate::atomic`]).
pub fn samples_csv(samples: &Samples, path: &Path) -> std::io::Result<()> {
    let mut w = csv::Writer::from_writer(Atomic::create(path)?);
    let mut head = vec!["time [s]".to_string()];
    head.extend(
        samples
            .channels
            .iter()
            .map(|c| format!("{} [{}]", c.name, c.unit)),
    );
    w.write_record(&head)?;
    // Numbers need no quoting: written straight into the buffer, no string per value.
    let mut out = std::io::BufWriter::new(w.into_inner().map_err(|e| e.into_error())?);
    for (t, row) in samples.times.iter().zip(&samples.rows) {
        write!(out, "{t:.9e}")?;
        for v in row {
            write!(out, ",{v:.9e}")?;
        }
        out.write_all(b"\n")?;
    }
    out.into_inner().map_err(|e| e.into_error())?.commit()
}

/// Writes the samples as an ASAM MDF4 file (`falcon_mdf`): one channel group, its master
/// `time [s]`, every output channel as a float64 with its unit; whole or not at all.
pub fn samples_mf4(samples: &Samples, path: &Path) -> std::io::Result<()> {
    let bad = |e: falcon_mdf::error::Mf4Error| std::io::Error::other(e.to_string());
    let mut w = falcon_mdf::write::Mf4Writer::new();
    let g = w.add_group(&samples.times).map_err(bad)?;
    let mut col = Vec::with_capacity(samples.times.len());
    for (c, info) in samples.channels.iter().enumerate() {
        col.clear();
        col.extend(samples.rows.iter().map(|r| r[c]));
        g.add_channel(&info.name, info.unit, &col).map_err(bad)?;
    }
    let mut out = Atomic::create(path)?;
    w.write(&mut out).map_err(bad)?;
    out.commit()
}

/// Writes `outputs.csv` (units in the headers), the plot pages of a scene (`plots.png`,
/// and `plots_outputs.png` for its `[[output]]` channels),
/// the HTML report (`report.html`, with the 3D view of `system` when the run recorded
/// poses) and `summary.json` into `dir`; the summary records the files and the report's
/// wall time. Each file is written whole or not at all ([`crate::atomic`]), the summary
/// last. `system` is the one the run integrated (`Job::system`).
pub fn write_run(run: &mut RunResult, system: &System, dir: &Path) -> Result<()> {
    write_run_as(run, system, dir, false)
}

/// [`write_run`], and with `mf4` the samples as `outputs.mf4` too ([`samples_mf4`]).
pub fn write_run_as(run: &mut RunResult, system: &System, dir: &Path, mf4: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let csv = dir.join("outputs.csv");
    samples_csv(&run.samples, &csv).map_err(|e| Error::io(&csv, e))?;
    run.summary.outputs_csv = Some(csv.display().to_string());
    if mf4 {
        let f = dir.join("outputs.mf4");
        samples_mf4(&run.samples, &f).map_err(|e| Error::io(&f, e))?;
        run.summary.outputs_mf4 = Some(f.display().to_string());
    }
    if run.summary.scene.is_some() {
        let plot = dir.join("plots.png");
        run.summary.plots = Some(match super::run_page(&run.samples, &plot) {
            Ok(()) => plot.display().to_string(),
            Err(e) => format!("not written: {e}"),
        });
        // The scene's `[[output]]` channels on a page of their own: the run page keeps
        // its fixed layout whatever the scene asks for.
        let asked = run
            .summary
            .scene
            .as_ref()
            .map(|s| s.output_channels.clone())
            .unwrap_or_default();
        if !asked.is_empty() {
            let page = dir.join("plots_outputs.png");
            run.summary.plots_outputs = Some(
                match super::run_outputs::outputs_page(&run.samples, &asked, &page) {
                    Ok(true) => page.display().to_string(),
                    Ok(false) => "not written: the run holds none of the channels".into(),
                    Err(e) => format!("not written: {e}"),
                },
            );
        }
    }
    let html = dir.join("report.html");
    run.summary.report = Some(html.display().to_string());
    let wall = Instant::now();
    let view = run
        .samples
        .poses
        .as_ref()
        .and_then(|p| super::scene3d::run_view(system, p));
    let page = super::html::run_report(
        &run.summary.name,
        &run.samples,
        &run.summary.to_json(),
        &run.samples.stats.step_history,
        view.as_deref(),
    );
    if let Err(e) = atomic::write(&html, page) {
        run.summary.report = Some(format!("not written: {e}"));
    }
    run.summary.report_wall_s = Some(wall.elapsed().as_secs_f64());
    // What reproduces the run's inputs from the files on disk (`--overrides FILE`).
    let ov = dir.join("overrides.toml");
    atomic::write(&ov, run.summary.produced_by.overrides_toml()).map_err(|e| Error::io(&ov, e))?;
    let path = dir.join("summary.json");
    let text = run.summary.to_json();
    atomic::write(&path, text).map_err(|e| Error::io(&path, e))
}
