//! Running sweep cases in parallel and writing and merging their summary.
//!
//! Nothing finished is lost: each finished case is appended to a journal
//! (`summary.csv.journal`, one JSON line per case) as it ends, the summary is written
//! whole at the end ([`crate::atomic`]), a case not run because the caller interrupted
//! the batch is recorded with status `interrupted`, and [`run_sweep_in`] with `resume`
//! runs only the cases neither the summary nor the journal holds.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::fingerprint::Fingerprint;
use super::{Case, Sweep};
use crate::error::{Error, Result};
use crate::job::{convergence, Job, ProducedBy};
use crate::scene::{channels, SceneError};
use towride_mbs::input::Loader;
use towride_mbs::progress::Progress;

pub use super::figures::{
    figures, Figures, CONVERGED, CONVERGENCE_WORST, CROSSBEAM_DEFLECTION, CROSSBEAM_ENERGY,
    UNCONVERGED,
};

/// What a case produced.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CaseRow {
    /// Case number in the full product.
    pub index: usize,
    /// The parameters' values (TOML text).
    pub values: Vec<String>,
    /// "completed", "failed" or "interrupted" (stopped, or not started, on request).
    pub status: String,
    /// Why it failed.
    pub error: Option<String>,
    /// Wall time of the case [s].
    pub wall_s: f64,
    /// The case's figures.
    pub figures: Figures,
}

/// Passes only the caller's stop request on to a case's run (the batch's bar counts
/// cases, not samples).
struct StopOnly<'a>(&'a dyn Progress);

impl Progress for StopOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// Runs `cases` on `jobs` threads with `run` (given the case, the sweep's scene, a
/// loader holding the case's overrides and the stop request); a failed or panicking case is recorded
/// and the others go on; once `progress` is cancelled no case starts (recorded
/// `interrupted`). `progress` counts finished cases; `done` sees each finished row.
pub fn run_cases<F>(
    sweep: &Sweep,
    cases: &[Case],
    jobs: usize,
    run: &F,
    progress: &dyn Progress,
    done: &(dyn Fn(&CaseRow) + Sync),
) -> Result<Vec<CaseRow>>
where
    F: Fn(&Case, &Path, &Loader, &dyn Progress) -> Result<Figures> + Sync,
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
                if progress.cancelled() {
                    return CaseRow {
                        index: c.index,
                        values: c.values.clone(),
                        status: "interrupted".into(),
                        error: Some("not started: the sweep was interrupted".into()),
                        wall_s: 0.0,
                        figures: vec![],
                    };
                }
                // The caller's overrides under the case's, with a record of use of its own.
                let loader = sweep.base.fresh().extended(c.overrides.clone());
                let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run(c, &sweep.scene, &loader, &StopOnly(progress))
                }));
                progress.inc(1);
                let (status, error, figures) = match out {
                    Ok(Ok(f)) => ("completed", None, f),
                    Ok(Err(e @ Error::Scene(SceneError::Interrupted { .. }))) => {
                        ("interrupted", Some(e.to_string()), vec![])
                    }
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
                let row = CaseRow {
                    index: c.index,
                    values: c.values.clone(),
                    status: status.into(),
                    error,
                    wall_s: t.elapsed().as_secs_f64(),
                    figures,
                };
                if row.status != "interrupted" {
                    done(&row);
                }
                row
            })
            .collect()
    });
    progress.finish();
    rows.sort_by_key(|r| r.index);
    Ok(rows)
}

/// Runs one case: the file (a mechanism or a scene) read through `loader`, integrated,
/// and its figures. A run the solver stops is a failed case.
pub fn run_case(path: &Path, loader: &Loader, stop: &dyn Progress) -> Result<Figures> {
    run_case_kept(path, loader, stop, None, None, None)
}

/// [`run_case`], keeping the run's files (also those of a run the solver stopped) in
/// its case folder under `keep` ([`super::cases`]).
fn run_case_kept(
    path: &Path,
    loader: &Loader,
    stop: &dyn Progress,
    keep: Option<(&Path, usize)>,
    check: Option<f64>,
    stamp: Option<&ProducedBy>,
) -> Result<Figures> {
    let mut job = Job::from_file(path, loader)?;
    if let Some(record) = stamp {
        // The caller's record (version, command line) with this case's overrides.
        let overrides = std::mem::take(&mut job.produced_by.overrides);
        job.produced_by = ProducedBy {
            overrides,
            ..record.clone()
        };
    }
    // Only a kept case writes a report with the 3D view.
    let job = if keep.is_some() {
        job
    } else {
        job.without_view()
    };
    let mut r = job.run(stop)?;
    if let (Some(threshold), true) = (check, r.failure().is_none()) {
        // The convergence verdict against the same case at a tighter tolerance.
        let companion = Job::from_file(path, loader)?
            .without_view()
            .tightened(convergence::TIGHTEN);
        let tight = companion.run(stop)?;
        r.summary.convergence = convergence::verdict(&r, &tight, job.solver.rtol, threshold);
    }
    if let (Some((cases, index)), None) = (keep, r.samples.interrupted) {
        super::cases::keep(&mut r, &job.system, cases, index)?;
    }
    r.require_completed()?;
    Ok(figures(&r))
}

/// Writes the summary CSV: case, parameters, status, wall time, every figure, error
/// (whole or not at all).
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
    let file = crate::atomic::Atomic::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = csv::Writer::from_writer(file);
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
    w.into_inner()
        .map_err(|e| Error::io(path, e.into_error()))?
        .commit()
        .map_err(|e| Error::io(path, e))
}

/// Version of a merged table's report (`sweep merge --json`). 2: the merged table's
/// figures are those of sweep summary version 5 ([`SCHEMA_VERSION`]); 3: version 6;
/// 4: version 7; 5: version 8.
pub const MERGE_SCHEMA_VERSION: u32 = 5;

/// What [`merge`] joined.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Merged {
    /// Layout version.
    pub schema_version: u32,
    /// The sweep's name (from the shards' JSON twins).
    pub sweep: String,
    /// Cases merged; equal to `cases_total` (a gap is an error).
    pub cases: usize,
    /// Cases of the whole product.
    pub cases_total: usize,
    /// The shard files joined.
    pub inputs: Vec<String>,
    /// The merged table's HTML page (`not written: ...` when it could not be).
    pub report: Option<String>,
    /// The merged table.
    pub out: String,
}

/// The JSON twin of a shard's summary CSV: the sweep's name, its case count and its
/// fingerprint.
/// A shard's sweep name, its case count, the rows it holds, and its fingerprint.
fn shard_meta(csv: &Path) -> Result<(String, usize, Option<usize>, Fingerprint)> {
    let json = csv.with_extension("json");
    let bad = |message: String| -> Error {
        SceneError::Merge {
            file: json.clone(),
            message,
        }
        .into()
    };
    let text = std::fs::read_to_string(&json).map_err(|e| {
        bad(format!(
            "cannot read the shard's JSON twin (written beside every summary CSV; it \
             says how many cases the sweep has): {e}"
        ))
    })?;
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| super::guard::not_json(&json, &e))?;
    check_version(&json, v["schema_version"].as_u64(), "merge it")?;
    let name = v["sweep"].as_str().map(String::from);
    let total = v["cases_total"].as_u64().map(|n| n as usize);
    let fp = serde_json::from_value::<Fingerprint>(v["fingerprint"].clone()).map_err(|_| {
        bad("no fingerprint: cannot tell which sweep this shard is of (run it again)".into())
    })?;
    let rows = v["cases"].as_u64().map(|n| n as usize);
    match (name, total) {
        (Some(n), Some(t)) => Ok((n, t, rows, fp)),
        _ => Err(bad("no `sweep` and `cases_total` fields".into())),
    }
}

/// Joins shard summaries (same columns, same sweep) into one table ordered by case,
/// written whole. Refused unless every case of the sweep appears exactly once and none
/// was interrupted: the case count comes from each shard's JSON twin.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<Merged> {
    let bad = |p: &Path, message: String| -> Error {
        SceneError::Merge {
            file: p.to_path_buf(),
            message,
        }
        .into()
    };
    let first = inputs
        .first()
        .ok_or_else(|| bad(out, "nothing to merge".into()))?;
    let (name, total, _, fp) = shard_meta(first)?;
    super::guard::merge_out(out, inputs, &fp)?;
    let mut header: Option<csv::StringRecord> = None;
    let mut rows: Vec<(usize, csv::StringRecord)> = Vec::new();
    for p in inputs {
        let (n, t, held, f) = shard_meta(p)?;
        if f.hash != fp.hash {
            return Err(bad(
                p,
                format!(
                    "a shard of another sweep than {} ({})",
                    first.display(),
                    fp.differences(&f).join("; ")
                ),
            ));
        }
        if n != name || t != total {
            return Err(bad(
                p,
                format!(
                    "a shard of sweep '{n}' with {t} cases, but {} is of '{name}' with {total}",
                    first.display()
                ),
            ));
        }
        let mut r = csv::ReaderBuilder::new()
            .flexible(true)
            .from_path(p)
            .map_err(|e| Error::io(p, e.into()))?;
        let h = r.headers().map_err(|e| bad(p, e.to_string()))?.clone();
        let status = h.iter().position(|c| c == "status");
        // Figures carry their unit in the header: those cells must be numbers.
        let numeric: Vec<usize> = (0..h.len())
            .filter(|&c| h[c].ends_with(']') && h[c].contains(" ["))
            .collect();
        let rows_before = rows.len();
        match &header {
            None => header = Some(h.clone()),
            Some(h0) if *h0 != h => {
                // The first column that differs, on the header line.
                let c = (0..h.len().max(h0.len()))
                    .find(|&c| h.get(c) != h0.get(c))
                    .unwrap_or(0);
                return Err(SceneError::MergeAt {
                    file: p.clone(),
                    line: 1,
                    field: h.get(c).unwrap_or("(missing)").to_string(),
                    message: format!(
                        "columns differ from {} (`{}` there): shards of different sweeps?",
                        first.display(),
                        h0.get(c).unwrap_or("(missing)")
                    ),
                }
                .into());
            }
            _ => {}
        }
        for (line, rec) in r.records().enumerate() {
            let at = |c: usize, message: String| -> Error {
                SceneError::MergeAt {
                    file: p.clone(),
                    line: line + 2,
                    field: h.get(c).unwrap_or("case").to_string(),
                    message,
                }
                .into()
            };
            let rec = rec.map_err(|e| at(0, e.to_string()))?;
            let idx: usize = rec
                .get(0)
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| at(0, "not a case number".into()))?;
            if idx >= total {
                return Err(at(0, format!("case {idx}, but the sweep has {total}")));
            }
            if status.and_then(|c| rec.get(c)) == Some("interrupted") {
                return Err(at(
                    status.unwrap_or(0),
                    format!(
                        "case {idx} was interrupted: finish the shard with `sweep --resume` first"
                    ),
                ));
            }
            if rec.len() != h.len() {
                return Err(at(
                    h.len() - 1,
                    format!("{} fields, the header has {}", rec.len(), h.len()),
                ));
            }
            for &c in &numeric {
                let v = rec[c].trim();
                if !v.is_empty() && !matches!(v, "NaN" | "nan") && v.parse::<f64>().is_err() {
                    return Err(at(c, format!("not a number: `{v}`")));
                }
            }
            rows.push((idx, rec));
        }
        // The JSON twin counts the shard's cases: fewer rows is a cut or spoilt table.
        let got = rows.len() - rows_before;
        if let Some(n) = held.filter(|&n| n != got) {
            // Blamed on the line after the last row read: where the missing rows belong.
            return Err(SceneError::MergeAt {
                file: p.clone(),
                line: got + 2,
                field: "case".into(),
                message: format!(
                    "{got} case rows, but its JSON twin says the shard ran {n}: the table is cut or spoilt (run the shard again)"
                ),
            }
            .into());
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
    if rows.len() != total {
        let have: BTreeSet<usize> = rows.iter().map(|(i, _)| *i).collect();
        let missing: Vec<usize> = (0..total).filter(|i| !have.contains(i)).collect();
        let shown: Vec<String> = missing.iter().take(10).map(|i| i.to_string()).collect();
        return Err(bad(
            out,
            format!(
                "{} of the sweep's {total} cases are missing (cases {}{}): a shard not given?",
                missing.len(),
                shown.join(", "),
                if missing.len() > 10 { ", ..." } else { "" }
            ),
        ));
    }
    let header = header.ok_or_else(|| bad(out, "nothing to merge".into()))?;
    let io = |e: csv::Error| Error::io(out, e.into());
    let file = crate::atomic::Atomic::create(out).map_err(|e| Error::io(out, e))?;
    let mut w = csv::Writer::from_writer(file);
    w.write_record(&header).map_err(io)?;
    for (_, r) in &rows {
        w.write_record(r).map_err(io)?;
    }
    w.into_inner()
        .map_err(|e| Error::io(out, e.into_error()))?
        .commit()
        .map_err(|e| Error::io(out, e))?;
    // Its JSON twin says what sweep it is, as a shard's does (a later merge into the
    // same file checks it).
    let twin = out.with_extension("json");
    let meta = serde_json::json!({
        "schema_version": SCHEMA_VERSION, "sweep": name, "cases_total": total,
        "fingerprint": fp, "merged_from": inputs,
    });
    crate::atomic::write(&twin, meta.to_string()).map_err(|e| Error::io(&twin, e))?;
    let report = Some(match super::page::write(out, &name) {
        Ok(files) => files.html.display().to_string(),
        Err(e) => format!("not written: {e}"),
    });
    Ok(Merged {
        schema_version: MERGE_SCHEMA_VERSION,
        report,
        sweep: name,
        cases: rows.len(),
        cases_total: total,
        inputs: inputs.iter().map(|p| p.display().to_string()).collect(),
        out: out.display().to_string(),
    })
}

/// Version of a sweep summary's layout (`summary.json`, and of the figures in the CSV
/// beside it and in the journal). 4: no signed peaks; the hitch force's max, min and
/// |peak|, the sensors' |peak| band-limited and raw ([`figures`]). 5: the ball force
/// components' damage-equivalent loads and the crossbeam points' largest equivalent
/// stress. 6: the DELs of the crossbeam points' equivalent stress and of the bracket
/// loads (per component, the worse bracket), each DEL in its channel's unit; and the
/// driver's floor comfort (ISO 2631-1 a_w and VDV per axis, total value;
/// [`super::figures`]). 7: each stress point's IIW damage per passage and the ball
/// force against the coupling's UN R55 D-value and test force. 8: the usage spectrum
/// with its provenance (`usage_spectrum`) and the ranking's robustness (`robustness`,
/// [`super::robust_run`]).
pub const SCHEMA_VERSION: u32 = 8;

/// Refuses a sweep file (a shard's JSON twin, a summary or journal to resume) written
/// with another layout version than [`SCHEMA_VERSION`]: an older one's figures (signed
/// peaks, other names) cannot be converted, as version 3 kept the signed peak but not
/// the max and min. `what`: what the caller would do with it.
pub(super) fn check_version(file: &Path, version: Option<u64>, what: &str) -> Result<()> {
    if version == Some(SCHEMA_VERSION as u64) {
        return Ok(());
    }
    let was = version.map_or("no schema_version (version 3 or older)".to_string(), |v| {
        format!("schema version {v}")
    });
    Err(SceneError::Merge {
        file: file.to_path_buf(),
        message: format!(
            "written with sweep summary {was}; this towride reads and writes version \
             {SCHEMA_VERSION} (figures max, min and abs_peak instead of signed peaks), and \
             an older table's figures cannot be converted: to {what}, run its cases again \
             with this version"
        ),
    }
    .into())
}

/// The signed-peak figures of sweep summaries before version 4 (`hitch_fx peak [N]`):
/// a summary CSV whose JSON twin is gone is recognised by them.
pub(super) fn legacy_figure(name: &str) -> bool {
    name.strip_suffix(" peak [N]")
        .is_some_and(|n| [channels::HITCH_FX, channels::HITCH_FY, channels::HITCH_FZ].contains(&n))
}

/// A sweep (or one shard of it) run and summarised.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SweepRun {
    /// Layout version.
    pub schema_version: u32,
    /// The sweep's name.
    pub sweep: String,
    /// "completed" (every case of the shard ran, completed or failed) or "interrupted"
    /// (some did not: `sweep --resume` finishes them).
    pub status: String,
    /// Cases of this shard.
    pub cases: usize,
    /// Cases of the whole product.
    pub cases_total: usize,
    /// Cases taken from an earlier, interrupted run (`--resume`).
    pub resumed: usize,
    /// This shard, (I, N).
    pub shard: (usize, usize),
    /// Threads used.
    pub jobs: usize,
    /// Cases that failed.
    pub failed: usize,
    /// Cases interrupted or not started.
    pub interrupted: usize,
    /// Wall time of the batch [s].
    pub wall_s: f64,
    /// The CSV written, once written.
    pub summary_csv: Option<String>,
    /// The sweep's HTML page, once written (`not written: ...` when it could not be).
    pub report: Option<String>,
    /// What the sweep is ([`super::fingerprint`]): resume and merge refuse others'.
    pub fingerprint: Option<Fingerprint>,
    /// Damage per km for the sweep file's `[usage]` spectrum ([`super::usage`]).
    pub usage: Option<Vec<super::usage::PerKm>>,
    /// The spectrum `usage` is of, with the source classes the study file gives it.
    pub usage_spectrum: Option<super::usage::Usage>,
    /// The ranking's robustness to the `[robustness]` block's values
    /// ([`super::robust_run`]).
    pub robustness: Option<super::robust_run::RobustnessRun>,
    /// Every case.
    pub rows: Vec<CaseRow>,
}

/// Runs shard `shard` = (I, N) of `sweep` on `jobs` threads, in memory only.
pub fn run_sweep(
    sweep: &Sweep,
    shard: (usize, usize),
    jobs: usize,
    progress: &dyn Progress,
) -> Result<SweepRun> {
    super::check::check(sweep, jobs)?;
    run_with(
        sweep,
        shard,
        jobs,
        Vec::new(),
        None,
        None,
        progress,
        &|_| {},
    )
}

#[allow(clippy::too_many_arguments)]
fn run_with(
    sweep: &Sweep,
    shard: (usize, usize),
    jobs: usize,
    prior: Vec<CaseRow>,
    keep: Option<&Path>,
    check: Option<f64>,
    progress: &dyn Progress,
    done: &(dyn Fn(&CaseRow) + Sync),
) -> Result<SweepRun> {
    let have: BTreeSet<usize> = prior.iter().map(|r| r.index).collect();
    let cases: Vec<Case> = sweep
        .shard(shard.0, shard.1)
        .into_iter()
        .filter(|c| !have.contains(&c.index))
        .collect();
    let wall = Instant::now();
    let resumed = prior.len();
    let run = |c: &Case, path: &Path, loader: &Loader, stop: &dyn Progress| {
        let stamp = Some(&sweep.produced_by);
        run_case_kept(path, loader, stop, keep.map(|k| (k, c.index)), check, stamp)
    };
    let mut rows = run_cases(sweep, &cases, jobs, &run, progress, done)?;
    rows.extend(prior);
    rows.sort_by_key(|r| r.index);
    let interrupted = rows.iter().filter(|r| r.status == "interrupted").count();
    Ok(SweepRun {
        schema_version: SCHEMA_VERSION,
        sweep: sweep.name.clone(),
        status: if interrupted > 0 {
            "interrupted"
        } else {
            "completed"
        }
        .into(),
        cases: rows.len(),
        cases_total: sweep.len(),
        resumed,
        shard,
        jobs,
        failed: rows.iter().filter(|r| r.status == "failed").count(),
        interrupted,
        wall_s: wall.elapsed().as_secs_f64(),
        summary_csv: None,
        report: None,
        fingerprint: None,
        usage: None,
        usage_spectrum: None,
        robustness: None,
        rows,
    })
}

/// The summary CSV of shard (I, N) in `dir`: `summary.csv`, or `summary_shardIofN.csv`.
pub fn summary_path(dir: &Path, shard: (usize, usize)) -> PathBuf {
    let (i, n) = shard;
    dir.join(if n > 1 {
        format!("summary_shard{i}of{n}.csv")
    } else {
        "summary.csv".into()
    })
}

/// Runs shard `shard` of `sweep` with its files in `dir`: each finished case goes to the
/// journal as it ends; at the end (or on interruption) the summary CSV and its JSON twin
/// are written whole and the journal removed. With `resume`, the cases that an earlier
/// run's summary or journal holds as completed or failed are kept, not run again, so
/// the summary equals an uninterrupted run's (wall times aside).
pub fn run_sweep_in(
    sweep: &Sweep,
    shard: (usize, usize),
    jobs: usize,
    dir: &Path,
    resume: bool,
    progress: &dyn Progress,
) -> Result<SweepRun> {
    let opts = Options {
        jobs,
        resume,
        keep_histories: false,
        check: None,
    };
    run_sweep_with(sweep, shard, dir, &opts, progress)
}

/// How [`run_sweep_with`] runs a sweep.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Cases run in parallel.
    pub jobs: usize,
    /// Keep the cases an earlier run left (see [`run_sweep_in`]).
    pub resume: bool,
    /// Keep each case's files in `dir/cases/<case id>/` ([`super::cases`]); a resumed
    /// run also runs again the completed cases whose folder is missing.
    pub keep_histories: bool,
    /// Give every case a convergence verdict (`run --check`) at this relative threshold:
    /// each case runs twice, the second time at a tolerance ten times tighter.
    pub check: Option<f64>,
}

/// [`run_sweep_in`] with all options; also writes the sweep's HTML page and figure
/// beside the summary ([`super::page`]).
pub fn run_sweep_with(
    sweep: &Sweep,
    shard: (usize, usize),
    dir: &Path,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<SweepRun> {
    super::guard::out_dir(dir)?;
    // Every parameter checked against the files before any case runs; the files read
    // are part of what the sweep is.
    let files = super::check::check(sweep, opts.jobs)?;
    let fp = Fingerprint::of(sweep, &files, &figures_kind(opts.check));
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let csv = summary_path(dir, shard);
    let journal = super::resume::journal_path(&csv);
    let cases = super::cases::cases_dir(dir);
    let keep = opts.keep_histories.then_some(cases.as_path());
    if keep.is_some() {
        std::fs::create_dir_all(&cases).map_err(|e| Error::io(&cases, e))?;
    }
    let mut prior = if opts.resume {
        super::resume::previous_rows(sweep, shard, &csv, &journal, &fp)?
    } else {
        Vec::new()
    };
    if let Some(k) = keep {
        prior.retain(|r| r.status != "completed" || super::cases::is_kept(k, r.index));
    }
    // A resumed sweep keeps its earlier cases only when they were checked as these will
    // be: a summary must not mix cases with and without a verdict.
    let checked = |r: &CaseRow| r.figures.iter().any(|(n, _)| n == CONVERGED);
    if let Some(r) = prior
        .iter()
        .find(|r| r.status == "completed" && checked(r) != opts.check.is_some())
    {
        return Err(SceneError::Merge {
            file: csv.clone(),
            message: format!(
                "case {} was run {} --check and this run is {} it: resume it as it was started, or remove the summary",
                r.index,
                if checked(r) { "with" } else { "without" },
                if opts.check.is_some() { "with" } else { "without" }
            ),
        }
        .into());
    }
    let jobs = opts.jobs;
    // The journal holds what the summary will hold; rewritten so a resumed run's old
    // entries stay with its new ones.
    let mut j = std::fs::File::create(&journal).map_err(|e| Error::io(&journal, e))?;
    super::resume::journal_head(&mut j, &fp).map_err(|e| Error::io(&journal, e))?;
    for r in &prior {
        super::resume::journal_line(&mut j, r).map_err(|e| Error::io(&journal, e))?;
    }
    let j = Mutex::new(j);
    let done = |r: &CaseRow| {
        if let Ok(mut f) = j.lock() {
            // A journal that cannot be written costs only the resume of this case.
            let _ = super::resume::journal_line(&mut f, r);
        }
    };
    let mut res = run_with(sweep, shard, jobs, prior, keep, opts.check, progress, &done)?;
    res.fingerprint = Some(fp);
    res.write_to(sweep, &csv)?;
    let _ = std::fs::remove_file(&journal);
    if let Some(u) = &sweep.usage {
        res.usage = Some(super::usage::per_km(&super::page::read(&csv)?, u));
        res.usage_spectrum = Some(u.clone());
    }
    if let Some(block) = &sweep.robustness {
        use super::robust_run::{run, RobustnessRun};
        res.robustness = Some(if shard != (0, 1) {
            RobustnessRun::not_run(
                block,
                "a shard has not the whole nominal ranking: run the sweep without --shard".into(),
            )
        } else if res.interrupted > 0 {
            RobustnessRun::not_run(
                block,
                "the sweep was interrupted: `--resume` finishes it and then runs the block".into(),
            )
        } else {
            run(sweep, block, &csv, dir, opts, progress)?
        });
    }
    let extra = serde_json::json!({
        "usage": res.usage_spectrum.as_ref().map(|s| serde_json::json!({"spectrum": s, "per_km": res.usage})),
        "robustness": res.robustness,
    });
    res.report = Some(match super::page::write_with(&csv, &sweep.name, &extra) {
        Ok(files) => files.html.display().to_string(),
        Err(e) => format!("not written: {e}"),
    });
    // The JSON twin names the page too.
    let json = csv.with_extension("json");
    let text = serde_json::to_string_pretty(&res).unwrap_or_default();
    crate::atomic::write(&json, text).map_err(|e| Error::io(&json, e))?;
    Ok(res)
}

/// What a case reports, for the fingerprint: the layout and the `--check` threshold.
fn figures_kind(check: Option<f64>) -> String {
    let check = check.map_or("no --check".to_string(), |t| format!("--check at {t}"));
    format!("summary v{SCHEMA_VERSION}, {check}")
}

impl SweepRun {
    /// Writes the summary CSV (`summary.csv`, or `summary_shardIofN.csv` for a shard)
    /// and its JSON twin into `dir`; returns the CSV's path.
    pub fn write(&mut self, sweep: &Sweep, dir: &Path) -> Result<PathBuf> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let csv = summary_path(dir, self.shard);
        self.write_to(sweep, &csv)?;
        Ok(csv)
    }

    fn write_to(&mut self, sweep: &Sweep, csv: &Path) -> Result<()> {
        write_summary(csv, sweep, &self.rows)?;
        self.summary_csv = Some(csv.display().to_string());
        let json = csv.with_extension("json");
        let text = serde_json::to_string_pretty(self).unwrap_or_default();
        crate::atomic::write(&json, text).map_err(|e| Error::io(&json, e))
    }
}
