//! Running sweep cases in parallel and writing, merging and plotting their summary.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;

use super::{Case, Sweep};
use crate::input::overrides;

/// Named figures of one case (peaks, energies), in a stable order.
pub type Figures = Vec<(String, f64)>;

/// What a case produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CaseRow {
    pub index: usize,
    pub values: Vec<String>,
    pub status: String,
    pub error: Option<String>,
    pub wall_s: f64,
    pub figures: Figures,
}

/// Runs `cases` on `jobs` threads with `run` (given the scene file, overrides active on
/// its thread); a failed or panicking case is recorded and the others go on.
pub fn run_cases<F>(
    sweep: &Sweep,
    cases: &[Case],
    jobs: usize,
    run: &F,
    progress: &dyn crate::progress::Progress,
) -> Result<Vec<CaseRow>, String>
where
    F: Fn(&Path) -> Result<Figures, String> + Sync,
{
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|e| e.to_string())?;
    let mut rows: Vec<CaseRow> = pool.install(|| {
        cases
            .par_iter()
            .map(|c| {
                let t = Instant::now();
                let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    overrides::with(&c.overrides, || run(&sweep.scene))
                }));
                progress.inc(1);
                let (status, error, figures) = match out {
                    Ok(Ok(f)) => ("completed", None, f),
                    Ok(Err(e)) => ("failed", Some(e), vec![]),
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
    rows.sort_by_key(|r| r.index);
    Ok(rows)
}

/// Writes the summary CSV: case, parameters, status, wall time, every figure, error.
pub fn write_summary(path: &Path, sweep: &Sweep, rows: &[CaseRow]) -> Result<(), String> {
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
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut head = vec!["case".to_string()];
    head.extend(sweep.parameters.iter().map(|p| p.name.clone()));
    head.extend(["status".into(), "wall_time [s]".into()]);
    head.extend(names.iter().cloned());
    head.push("error".into());
    w.write_record(&head).map_err(|e| e.to_string())?;
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
        w.write_record(&rec).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

/// Joins shard summaries (same columns) into one, ordered by case.
pub fn merge(inputs: &[std::path::PathBuf], out: &Path) -> Result<usize, String> {
    let mut header: Option<csv::StringRecord> = None;
    let mut rows: Vec<(usize, csv::StringRecord)> = Vec::new();
    for p in inputs {
        let mut r = csv::Reader::from_path(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let h = r
            .headers()
            .map_err(|e| format!("{}: {e}", p.display()))?
            .clone();
        match &header {
            None => header = Some(h),
            Some(h0) if *h0 != h => {
                return Err(format!(
                    "{}: columns differ from {} (shards of different sweeps?)",
                    p.display(),
                    inputs[0].display()
                ))
            }
            _ => {}
        }
        for (line, rec) in r.records().enumerate() {
            let rec = rec.map_err(|e| format!("{}: {e}", p.display()))?;
            let idx: usize = rec.get(0).and_then(|s| s.parse().ok()).ok_or_else(|| {
                format!(
                    "{}:{}: first column is not a case number",
                    p.display(),
                    line + 2
                )
            })?;
            rows.push((idx, rec));
        }
    }
    rows.sort_by_key(|(i, _)| *i);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(format!(
            "case {} appears twice (the same shard merged twice?)",
            w[0].0
        ));
    }
    let header = header.ok_or("nothing to merge")?;
    let mut w = csv::Writer::from_path(out).map_err(|e| format!("{}: {e}", out.display()))?;
    w.write_record(&header).map_err(|e| e.to_string())?;
    for (_, r) in &rows {
        w.write_record(r).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    Ok(rows.len())
}
