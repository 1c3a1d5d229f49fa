//! Running sweep cases in parallel and writing and merging their summary.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;

use super::{Case, Sweep};
use crate::error::{Error, Result};
use crate::input::Loader;
use crate::job::{Job, RunResult};
use crate::progress::{Progress, Silent};
use crate::scene::SceneError;

/// Named figures of one case (peaks, energies), in a stable order.
pub type Figures = Vec<(String, f64)>;

/// What a case produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CaseRow {
    /// Case number in the full product.
    pub index: usize,
    /// The parameters' values (TOML text).
    pub values: Vec<String>,
    /// "completed" or "failed".
    pub status: String,
    /// Why it failed.
    pub error: Option<String>,
    /// Wall time of the case [s].
    pub wall_s: f64,
    /// The case's figures.
    pub figures: Figures,
}

/// Runs `cases` on `jobs` threads with `run` (given the sweep's scene and a loader
/// holding the case's overrides); a failed or panicking case is recorded and the others
/// go on. `progress` counts finished cases.
pub fn run_cases<F>(
    sweep: &Sweep,
    cases: &[Case],
    jobs: usize,
    run: &F,
    progress: &dyn Progress,
) -> Result<Vec<CaseRow>>
where
    F: Fn(&Path, &Loader) -> Result<Figures> + Sync,
{
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|e| Error::io("thread pool", std::io::Error::other(e.to_string())))?;
    progress.begin(cases.len() as u64);
    let mut rows: Vec<CaseRow> = pool.install(|| {
        cases
            .par_iter()
            .map(|c| {
                let t = Instant::now();
                let loader = Loader::with_overrides(c.overrides.clone());
                let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run(&sweep.scene, &loader)
                }));
                progress.inc(1);
                let (status, error, figures) = match out {
                    Ok(Ok(f)) => ("completed", None, f),
                    Ok(Err(e)) => ("failed", Some(e.to_string()), vec![]),
                    Err(p) => {
                        let msg = p
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_else(|| "panic".into());
                        ("failed", Some(format!("internal error: {msg}")), vec![])
                    }
                };
                CaseRow {
                    index: c.index,
                    values: c.values.clone(),
                    status: status.into(),
                    error,
                    wall_s: t.elapsed().as_secs_f64(),
                    figures,
                }
            })
            .collect()
    });
    progress.finish();
    rows.sort_by_key(|r| r.index);
    Ok(rows)
}

/// Runs one case: the file (a mechanism or a scene) read through `loader`, integrated,
/// and its figures. A run the solver stops is a failed case.
pub fn run_case(path: &Path, loader: &Loader) -> Result<Figures> {
    let job = Job::from_file(path, loader)?;
    let r = job.run(&Silent)?;
    r.require_completed()?;
    Ok(figures(&r))
}

/// The figures a sweep records of a run. A mechanism: every channel's max and min and
/// the steps. A vehicle scene: peak hitch force components, peak acceleration per
/// sensor, the crossbeam's peak deflection and strain energy, solver effort.
pub fn figures(r: &RunResult) -> Figures {
    let s = &r.summary;
    let mut out = Figures::new();
    if s.scene.is_none() {
        for (name, c) in &s.channels {
            out.push((format!("{name} max [{}]", c.unit), c.max));
            out.push((format!("{name} min [{}]", c.unit), c.min));
        }
        out.push(("steps".into(), s.solver.steps as f64));
        return out;
    }
    for n in ["hitch_fx", "hitch_fy", "hitch_fz"] {
        if let Some(c) = s.channels.get(n) {
            out.push((format!("{n} peak [N]"), c.peak));
        }
    }
    for (name, c) in &s.channels {
        if name.starts_with("acc_") || name == "trailer_ax" {
            out.push((format!("{name} peak [m/s^2]"), c.peak.abs()));
        }
    }
    if let (Some(x), Some(y), Some(z)) = (
        r.channel("hitch_deflection_x"),
        r.channel("hitch_deflection_y"),
        r.channel("hitch_deflection_z"),
    ) {
        let d = (0..x.len()).fold(0.0f64, |m, k| {
            m.max((x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt())
        });
        out.push(("crossbeam peak deflection [m]".into(), d));
    }
    if let Some(c) = s.channels.get("hitch_strain_energy") {
        out.push(("crossbeam peak strain energy [J]".into(), c.peak.abs()));
    }
    out.push(("steps".into(), s.solver.steps as f64));
    out.push(("run wall time [s]".into(), s.start_wall_s + s.wall_s));
    out
}

/// Writes the summary CSV: case, parameters, status, wall time, every figure, error.
pub fn write_summary(path: &Path, sweep: &Sweep, rows: &[CaseRow]) -> Result<()> {
    let names: Vec<String> = {
        let mut seen = BTreeSet::new();
        let mut v = Vec::new();
        for r in rows {
            for (n, _) in &r.figures {
                if seen.insert(n.clone()) {
                    v.push(n.clone());
                }
            }
        }
        v
    };
    let io = |e: csv::Error| Error::io(path, e.into());
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    let mut head = vec!["case".to_string()];
    head.extend(sweep.parameters.iter().map(|p| p.name.clone()));
    head.extend(["status".into(), "wall_time [s]".into()]);
    head.extend(names.iter().cloned());
    head.push("error".into());
    w.write_record(&head).map_err(io)?;
    for r in rows {
        let mut rec = vec![r.index.to_string()];
        rec.extend(r.values.iter().map(|v| v.trim_matches('"').to_string()));
        rec.push(r.status.clone());
        rec.push(format!("{:.4}", r.wall_s));
        for n in &names {
            rec.push(
                r.figures
                    .iter()
                    .find(|(k, _)| k == n)
                    .map_or(String::new(), |(_, v)| format!("{v:.6e}")),
            );
        }
        rec.push(r.error.clone().unwrap_or_default());
        w.write_record(&rec).map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Joins shard summaries (same columns) into one, ordered by case.
pub fn merge(inputs: &[std::path::PathBuf], out: &Path) -> Result<usize> {
    let bad = |p: &Path, message: String| -> Error {
        SceneError::Merge {
            file: p.to_path_buf(),
            message,
        }
        .into()
    };
    let mut header: Option<csv::StringRecord> = None;
    let mut rows: Vec<(usize, csv::StringRecord)> = Vec::new();
    for p in inputs {
        let mut r = csv::Reader::from_path(p).map_err(|e| Error::io(p, e.into()))?;
        let h = r.headers().map_err(|e| bad(p, e.to_string()))?.clone();
        match &header {
            None => header = Some(h),
            Some(h0) if *h0 != h => {
                return Err(bad(
                    p,
                    format!(
                        "columns differ from {} (shards of different sweeps?)",
                        inputs[0].display()
                    ),
                ))
            }
            _ => {}
        }
        for (line, rec) in r.records().enumerate() {
            let rec = rec.map_err(|e| bad(p, e.to_string()))?;
            let idx: usize = rec.get(0).and_then(|s| s.parse().ok()).ok_or_else(|| {
                bad(
                    p,
                    format!("line {}: first column is not a case number", line + 2),
                )
            })?;
            rows.push((idx, rec));
        }
    }
    rows.sort_by_key(|(i, _)| *i);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(bad(
            out,
            format!(
                "case {} appears twice (the same shard merged twice?)",
                w[0].0
            ),
        ));
    }
    let header = header.ok_or_else(|| bad(out, "nothing to merge".into()))?;
    let io = |e: csv::Error| Error::io(out, e.into());
    let mut w = csv::Writer::from_path(out).map_err(io)?;
    w.write_record(&header).map_err(io)?;
    for (_, r) in &rows {
        w.write_record(r).map_err(io)?;
    }
    w.flush().map_err(|e| Error::io(out, e))?;
    Ok(rows.len())
}

/// Version of a sweep summary's layout (`summary.json`).
pub const SCHEMA_VERSION: u32 = 1;

/// A sweep (or one shard of it) run and summarised.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SweepRun {
    /// Layout version.
    pub schema_version: u32,
    /// The sweep's name.
    pub sweep: String,
    /// Cases run here.
    pub cases: usize,
    /// Cases of the whole product.
    pub cases_total: usize,
    /// This shard, (I, N).
    pub shard: (usize, usize),
    /// Threads used.
    pub jobs: usize,
    /// Cases that failed.
    pub failed: usize,
    /// Wall time of the batch [s].
    pub wall_s: f64,
    /// The CSV written, once written.
    pub summary_csv: Option<String>,
    /// Every case.
    pub rows: Vec<CaseRow>,
}

/// Runs shard `shard` = (I, N) of `sweep` on `jobs` threads.
pub fn run_sweep(
    sweep: &Sweep,
    shard: (usize, usize),
    jobs: usize,
    progress: &dyn Progress,
) -> Result<SweepRun> {
    let cases = sweep.shard(shard.0, shard.1);
    let wall = Instant::now();
    let rows = run_cases(sweep, &cases, jobs, &run_case, progress)?;
    Ok(SweepRun {
        schema_version: SCHEMA_VERSION,
        sweep: sweep.name.clone(),
        cases: rows.len(),
        cases_total: sweep.len(),
        shard,
        jobs,
        failed: rows.iter().filter(|r| r.status != "completed").count(),
        wall_s: wall.elapsed().as_secs_f64(),
        summary_csv: None,
        rows,
    })
}

impl SweepRun {
    /// Writes the summary CSV (`summary.csv`, or `summary_shardIofN.csv` for a shard)
    /// and its JSON twin into `dir`; returns the CSV's path.
    pub fn write(&mut self, sweep: &Sweep, dir: &Path) -> Result<std::path::PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let (i, n) = self.shard;
        let name = if n > 1 {
            format!("summary_shard{i}of{n}.csv")
        } else {
            "summary.csv".into()
        };
        let csv = dir.join(name);
        write_summary(&csv, sweep, &self.rows)?;
        self.summary_csv = Some(csv.display().to_string());
        let json = csv.with_extension("json");
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        std::fs::write(&json, text).map_err(|e| Error::io(&json, e))?;
        Ok(csv)
    }
}
