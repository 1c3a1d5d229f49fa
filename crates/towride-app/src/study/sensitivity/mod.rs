//! Which inputs matter: one-at-a-time elasticities and Morris screening of a scene's (or
//! a mechanism's) outputs over its property-file values ([`params`]), the runs in
//! parallel, figures and tables written without the runs' own reports.
//!
//! - OAT: per parameter two runs at 0.9 and 1.1 times its value; the elasticity
//!   d ln y / d ln p by the central difference (ln y+ - ln y-) / (ln 1.1 - ln 0.9).
//! - Morris ([`morris`]): r trajectories of k + 1 runs over `p` levels of each
//!   parameter's range (its value times 1 -+ `range`, narrowed to the plausibility table
//!   [`towride_mbs::input::bounds`] where that is narrower); mu* and sigma per output, in the
//!   output's unit per unit of the normalised range, and mu* relative to the base output.
//!
//! A run that fails is recorded with its parameter values and error; the others go on,
//! and the study says at its top (`status`, `note`) that its figures are partial. A
//! study stopped on request (Ctrl-C) keeps what ran, calls the runs it never started
//! "not run" (not failed) and leaves a figure it cannot compute empty, never NaN.

pub mod assumed;
pub mod morris;
pub mod numbers;
pub mod outputs;
pub mod page;
pub mod params;
pub mod tornado;
pub mod write;

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::job::Job;
pub use outputs::OutputSpec;
pub use params::Param;
use towride_mbs::input::Loader;
use towride_mbs::input::Override;
use towride_mbs::progress::Progress;

/// Version of the study's JSON layout. 2: outputs `CHANNEL.abs_peak`, `.max`, `.min`
/// (`.peak` and `.peak100` are gone; band-limited channels by their own names).
pub const SCHEMA_VERSION: u32 = 2;

/// The screening method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// One at a time, central differences at +-10 %.
    Oat,
    /// Morris elementary effects.
    Morris,
}

impl Method {
    /// The method as engineers write it ("OAT", "Morris"): the JSON's snake_case name
    /// (`oat`) is for programs, a Debug print of it read "Oat".
    pub fn short(self) -> &'static str {
        match self {
            Method::Oat => "OAT",
            Method::Morris => "Morris",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Oat => "OAT (one-at-a-time) study",
            Method::Morris => "Morris screening (elementary effects)",
        })
    }
}

/// What to study.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Scene or mechanism file.
    pub file: PathBuf,
    /// Parameters named `FILE:PATH` (empty: discovered in `groups`).
    pub params: Vec<String>,
    /// Groups searched when `params` is empty (empty: [`DEFAULT_GROUPS`]).
    pub groups: Vec<String>,
    /// Outputs (empty: the defaults of [`outputs::defaults`]).
    pub outputs: Vec<String>,
    /// OAT or Morris.
    pub method: Method,
    /// Morris trajectories.
    pub trajectories: usize,
    /// Morris levels (even).
    pub levels: usize,
    /// Morris range: each value times 1 -+ this (OAT varies by +-10 % and ignores it).
    pub range: f64,
    /// Morris seed.
    pub seed: u64,
    /// Parallel runs.
    pub jobs: usize,
    /// The caller's overrides (`--set`, `--overrides`), under every run's own.
    pub base: Loader,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            file: PathBuf::new(),
            params: Vec::new(),
            groups: Vec::new(),
            outputs: Vec::new(),
            method: Method::Oat,
            trajectories: 10,
            levels: 4,
            range: 0.3,
            seed: 1,
            jobs: 2,
            base: Loader::new(),
        }
    }
}

/// An output with its base value.
#[derive(Clone, Debug, Serialize)]
pub struct OutputInfo {
    /// `CHANNEL.measure`.
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// Value of the base run.
    pub base: f64,
    /// A `.abs_peak` output's signed sample at the base run's |peak|: whether the peak
    /// was a pull or a push, which its magnitude hides.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_signed: Option<f64>,
}

/// One parameter's results, per output in `Study::outputs` order.
#[derive(Clone, Debug, Serialize)]
pub struct ParamResult {
    /// The parameter.
    pub param: Param,
    /// OAT elasticities d ln y / d ln p (`None`: a run failed, or y is 0 or changes sign).
    pub elasticity: Vec<Option<f64>>,
    /// Morris statistics.
    pub morris: Vec<morris::Effects>,
    /// Morris mu* relative to the base output.
    pub mu_star_rel: Vec<f64>,
    /// Morris range of the scale factor [low, high].
    pub range: [f64; 2],
    /// Why a figure is missing (a base value of 0 has no relative change; no pair of
    /// Morris runs completed).
    pub note: Option<String>,
}

/// A run that failed.
#[derive(Clone, Debug, Serialize)]
pub struct FailedRun {
    /// The parameter values of the run (`name=factor`).
    pub changes: String,
    /// The error.
    pub error: String,
}

/// A finished study.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    /// Layout version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// "completed" (every run completed), "partial" (some failed: the figures they take
    /// part in are missing) or "interrupted" (stopped on request; some not run).
    pub status: String,
    /// What the reader must know first when the status is not "completed".
    pub note: Option<String>,
    /// The caller's overrides under every run (`FILE:PATH = VALUE`): a study of a
    /// shortened run is not one of the scene as filed.
    pub overrides: Vec<String>,
    /// Version, commit and command line of the program that made the study (the binary
    /// fills them in before writing).
    pub produced_by: crate::job::ProducedBy,
    /// The scene or mechanism.
    pub file: String,
    /// OAT or Morris.
    pub method: Method,
    /// The outputs.
    pub outputs: Vec<OutputInfo>,
    /// The parameters studied.
    pub params: Vec<ParamResult>,
    /// Values found but not studied: the model does not depend on them, or they cannot
    /// be varied (the reason follows the name).
    pub inactive: Vec<String>,
    /// Runs that failed.
    pub failed: Vec<FailedRun>,
    /// Runs not made: the study was interrupted before they started (or while they ran).
    pub not_run: usize,
    /// Runs made (the base run included).
    pub runs: usize,
    /// Parallel runs.
    pub jobs: usize,
    /// Morris trajectories, levels and seed.
    pub trajectories: usize,
    /// Morris levels.
    pub levels: usize,
    /// Morris seed.
    pub seed: u64,
    /// Wall time of the runs [s].
    pub runs_wall_s: f64,
    /// Wall time of the whole study (discovery included) [s].
    pub wall_s: f64,
    /// Files written.
    pub written: Vec<String>,
}

impl Study {
    /// Parameters ranked by output `output`'s |elasticity| (OAT) or mu* (Morris),
    /// largest first.
    pub fn ranking(&self, output: usize) -> Vec<&ParamResult> {
        let key = |p: &ParamResult| match self.method {
            Method::Oat => p
                .elasticity
                .get(output)
                .copied()
                .flatten()
                .map_or(-1.0, f64::abs),
            Method::Morris => p
                .mu_star_rel
                .get(output)
                .copied()
                .filter(|v| v.is_finite())
                .unwrap_or(-1.0),
        };
        let mut v: Vec<&ParamResult> = self.params.iter().collect();
        v.sort_by(|a, b| key(b).total_cmp(&key(a)));
        v
    }
}

/// Passes only the caller's stop request on to a run.
struct StopOnly<'a>(&'a dyn Progress);

impl Progress for StopOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// The groups searched when none are named: the hitch, the trailer, the tyres and a
/// `simple` vehicle's own file (its masses, ride frequencies, damping ratios, tyre).
pub const DEFAULT_GROUPS: [&str; 4] = ["hitch", "trailer", "tyres", "vehicle"];

/// The parameters of `s`: named, or discovered and filtered for activity.
pub fn parameters(s: &Settings) -> Result<(Vec<Param>, Vec<String>)> {
    let all = params::candidates(&s.file, &[])?;
    if !s.params.is_empty() {
        return Ok((params::named(&all, &s.params)?, Vec::new()));
    }
    let groups: Vec<String> = if s.groups.is_empty() {
        DEFAULT_GROUPS.map(String::from).to_vec()
    } else {
        s.groups.clone()
    };
    let mut present: Vec<&str> = all.iter().map(|p| p.group.as_str()).collect();
    present.sort();
    present.dedup();
    let present = present.join(", ");
    let found: Vec<Param> = all
        .iter()
        .filter(|p| groups.contains(&p.group))
        .cloned()
        .collect();
    if found.is_empty() {
        return Err(towride_mbs::input::InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: "--group".into(),
            message: format!(
                "no stiffness, damping or mass value in the groups {} of {} (its values are \
                 in the groups {present}: name them with --group, or see --list)",
                groups.join(", "),
                s.file.display()
            ),
            kind: Default::default(),
        }
        .into());
    }
    // Active: a 10 % change alters the assembled model. One that cannot be changed (a
    // value towride derives from another file's) is left out, with the reason.
    let print = |ov: Vec<Override>| -> std::result::Result<String, String> {
        Job::from_file(&s.file, &s.base.fresh().extended(ov))
            .map(|j| format!("{:?}", j.system.model))
            .map_err(|e| e.to_string())
    };
    let base = print(Vec::new()).ok();
    let pool = pool(s.jobs)?;
    let active: Vec<std::result::Result<bool, String>> = pool.install(|| {
        found
            .par_iter()
            .map(|p| match (&base, print(vec![p.scaled(1.1)])) {
                (None, _) => Ok(true),
                (Some(b), Ok(m)) => Ok(m != *b),
                (Some(_), Err(e)) => Err(e),
            })
            .collect()
    });
    let mut keep = Vec::new();
    let mut inactive = Vec::new();
    for (p, a) in found.into_iter().zip(active) {
        match a {
            Ok(true) => keep.push(p),
            Ok(false) => inactive.push(p.name),
            Err(e) => inactive.push(format!("{} (cannot be varied: {e})", p.name)),
        }
    }
    Ok((keep, inactive))
}

fn pool(jobs: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .map_err(|e| Error::io("thread pool", std::io::Error::other(e.to_string())))
}

/// One run's outputs, why it failed, or that it was not run (interrupted).
enum Outcome {
    /// The outputs and, for `.abs_peak` ones, the signed value at the peak.
    Done(Vec<f64>, Vec<Option<f64>>),
    Failed(String),
    NotRun,
}

/// Runs `cases` (each a set of overrides) in parallel; failures and panics recorded.
fn run_all(
    s: &Settings,
    specs: &[OutputSpec],
    cases: &[Vec<Override>],
    progress: &dyn Progress,
) -> Result<Vec<Outcome>> {
    let pool = pool(s.jobs)?;
    progress.begin(cases.len() as u64);
    let out = pool.install(|| {
        cases
            .par_iter()
            .map(|ov| {
                if progress.cancelled() {
                    return Outcome::NotRun;
                }
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
                    || -> Result<(Vec<f64>, Vec<Option<f64>>)> {
                        let loader = s.base.fresh().extended(ov.clone());
                        let job = Job::from_file(&s.file, &loader)?.without_view();
                        let r = job.run(&StopOnly(progress))?;
                        r.require_completed()?;
                        Ok((
                            outputs::evaluate(specs, &r)?,
                            outputs::signed_peaks(specs, &r),
                        ))
                    },
                ));
                progress.inc(1);
                match r {
                    Ok(Ok((v, signed))) => Outcome::Done(v, signed),
                    Ok(Err(Error::Scene(crate::scene::SceneError::Interrupted { .. }))) => {
                        Outcome::NotRun
                    }
                    Ok(Err(e)) => Outcome::Failed(e.to_string()),
                    Err(_) => Outcome::Failed("internal error (panic) in the run".to_string()),
                }
            })
            .collect()
    });
    progress.finish();
    Ok(out)
}

/// Runs the study `s`.
pub fn run(s: &Settings, progress: &dyn Progress) -> Result<Study> {
    check_settings(s)?;
    let wall = Instant::now();
    let (params, inactive) = parameters(s)?;
    let base_job = Job::from_file(&s.file, &s.base.fresh())?;
    let specs = outputs::resolve(&s.outputs, &base_job)?;
    drop(base_job);
    let k = params.len();
    let mut cases: Vec<Vec<Override>> = vec![Vec::new()];
    let mut labels: Vec<String> = vec!["base".into()];
    let ranges: Vec<[f64; 2]> = params.iter().map(|p| range_of(p, s.range)).collect();
    let design = match s.method {
        Method::Oat => {
            for p in &params {
                for f in [0.9, 1.1] {
                    cases.push(vec![p.scaled(f)]);
                    labels.push(format!("{}={f}", p.name));
                }
            }
            Vec::new()
        }
        Method::Morris => {
            let d = morris::design(k, s.trajectories, s.levels.max(2), s.seed);
            for t in &d {
                for x in &t.points {
                    let ov: Vec<Override> = params
                        .iter()
                        .zip(x)
                        .zip(&ranges)
                        .map(|((p, &xi), r)| p.scaled(r[0] + xi * (r[1] - r[0])))
                        .collect();
                    labels.push(
                        x.iter()
                            .zip(&ranges)
                            .zip(&params)
                            .map(|((xi, r), p)| {
                                format!("{}={:.3}", p.name, r[0] + xi * (r[1] - r[0]))
                            })
                            .collect::<Vec<_>>()
                            .join(" "),
                    );
                    cases.push(ov);
                }
            }
            d
        }
    };
    let t_runs = Instant::now();
    let res = run_all(s, &specs, &cases, progress)?;
    let runs_wall_s = t_runs.elapsed().as_secs_f64();
    let failed: Vec<FailedRun> = res
        .iter()
        .zip(&labels)
        .filter_map(|(r, l)| match r {
            Outcome::Failed(e) => Some(FailedRun {
                changes: l.clone(),
                error: e.clone(),
            }),
            _ => None,
        })
        .collect();
    let not_run = res.iter().filter(|r| matches!(r, Outcome::NotRun)).count();
    let (base, base_signed) = match &res[0] {
        Outcome::Done(v, signed) => (v.clone(), signed.clone()),
        Outcome::Failed(e) => {
            return Err(crate::scene::SceneError::RunFailed {
                name: format!("{} (the study's base run)", s.file.display()),
                t: 0.0,
                message: e.clone(),
            }
            .into())
        }
        Outcome::NotRun => {
            return Err(crate::scene::SceneError::Interrupted {
                name: format!("{} (the study's base run)", s.file.display()),
                t: 0.0,
            }
            .into())
        }
    };
    let outputs: Vec<OutputInfo> = specs
        .iter()
        .zip(&base)
        .zip(&base_signed)
        .map(|((o, b), signed)| OutputInfo {
            name: o.name(),
            unit: o.unit.clone(),
            base: *b,
            base_signed: *signed,
        })
        .collect();
    let no = outputs.len();
    let at = |i: usize, o: usize| match &res[i] {
        Outcome::Done(v, _) => Some(v[o]),
        _ => None,
    };
    let mut results: Vec<ParamResult> = params
        .iter()
        .zip(&ranges)
        .map(|(p, r)| ParamResult {
            param: p.clone(),
            elasticity: Vec::new(),
            morris: Vec::new(),
            mu_star_rel: Vec::new(),
            range: *r,
            // Scaling 0 leaves it 0: no relative change, so no elasticity or effect.
            note: (p.base_value() == 0.0).then(|| {
                "base value 0: a relative change (elasticity) is undefined; not varied".into()
            }),
        })
        .collect();
    match s.method {
        Method::Oat => {
            let dl = 1.1f64.ln() - 0.9f64.ln();
            for (j, pr) in results.iter_mut().enumerate() {
                let zero = pr.note.is_some();
                pr.elasticity = (0..no)
                    .map(|o| match (at(1 + 2 * j, o), at(2 + 2 * j, o)) {
                        // (p / y) dy/dp is d ln|y| / d ln p for either sign of y: a
                        // negative output (a `.min`) has an elasticity too, as long as
                        // both runs keep its sign.
                        (Some(a), Some(b)) if a * b > 0.0 && !zero => {
                            Some((b.abs().ln() - a.abs().ln()) / dl)
                        }
                        _ => None,
                    })
                    .collect();
            }
        }
        Method::Morris => {
            for o in 0..no {
                let mut idx = 1;
                let y: Vec<Vec<Option<f64>>> = design
                    .iter()
                    .map(|t| {
                        let v = (0..t.points.len()).map(|j| at(idx + j, o)).collect();
                        idx += t.points.len();
                        v
                    })
                    .collect();
                for (pr, e) in results
                    .iter_mut()
                    .zip(morris::effects(&design, &y, s.levels.max(2)))
                {
                    // No completed pair (runs failed or not run): no figure, not NaN.
                    let rel = e.mu_star / outputs[o].base.abs();
                    let defined = rel.is_finite() && pr.param.base_value() != 0.0;
                    pr.mu_star_rel.push(if defined { rel } else { f64::NAN });
                    if e.effects == 0 && pr.note.is_none() {
                        pr.note = Some("no pair of runs completed: no elementary effect".into());
                    }
                    pr.morris.push(e);
                }
            }
        }
    }
    let (status, note) = verdict(cases.len(), failed.len(), not_run);
    Ok(Study {
        schema_version: SCHEMA_VERSION,
        status,
        note,
        overrides: s
            .base
            .overrides()
            .map(|o| format!("{}:{} = {}", o.file, o.path.trim(), o.value.trim()))
            .collect(),
        produced_by: Default::default(),
        file: s.file.display().to_string(),
        method: s.method,
        outputs,
        params: results,
        inactive,
        failed,
        not_run,
        runs: cases.len(),
        jobs: s.jobs,
        trajectories: if s.method == Method::Morris {
            s.trajectories
        } else {
            0
        },
        levels: s.levels,
        seed: s.seed,
        runs_wall_s,
        wall_s: wall.elapsed().as_secs_f64(),
        written: Vec::new(),
    })
}

/// The study's status and the sentence its outputs open with (see [`Study::status`]).
fn verdict(runs: usize, failed: usize, not_run: usize) -> (String, Option<String>) {
    if not_run > 0 {
        let f = if failed > 0 {
            format!(" and {failed} failed")
        } else {
            String::new()
        };
        return (
            "interrupted".into(),
            Some(format!(
                "interrupted: {not_run} of {runs} runs not run{f}; the figures are partial \
                 (those without a completed run are left empty)"
            )),
        );
    }
    if failed > 0 {
        return (
            "partial".into(),
            Some(format!(
                "{failed} of {runs} runs failed: the figures they take part in are missing \
                 (the failures are listed with the study)"
            )),
        );
    }
    ("completed".into(), None)
}

/// Settings a study cannot be made with, refused before any run.
fn check_settings(s: &Settings) -> Result<()> {
    let bad = |field: &str, message: String| -> Error {
        towride_mbs::input::InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: field.into(),
            message,
            kind: Default::default(),
        }
        .into()
    };
    if s.method == Method::Morris
        && !(MIN_TRAJECTORIES..=MAX_TRAJECTORIES).contains(&s.trajectories)
    {
        return Err(bad(
            "--trajectories",
            format!(
                "{}: Morris needs {MIN_TRAJECTORIES} to {MAX_TRAJECTORIES} trajectories \
                 (sigma takes two elementary effects per parameter)",
                s.trajectories
            ),
        ));
    }
    if !(s.range > 0.0 && s.range < 1.0) {
        return Err(bad(
            "--range",
            format!("{}: a fraction between 0 and 1", s.range),
        ));
    }
    Ok(())
}

/// Morris trajectories accepted: two give sigma its first degree of freedom; a thousand
/// is far beyond screening practice (10 to 50) and bounds the runs.
pub const MIN_TRAJECTORIES: usize = 2;
/// See [`MIN_TRAJECTORIES`].
pub const MAX_TRAJECTORIES: usize = 1000;

/// The Morris range of a parameter's scale factor: 1 -+ `range`, narrowed to the
/// plausibility bounds of its key.
fn range_of(p: &Param, range: f64) -> [f64; 2] {
    let key = p.path.rsplit('.').next().unwrap_or(&p.path);
    let b = towride_mbs::input::bounds::for_key(key);
    let v = p.base_value().abs();
    let (mut lo, mut hi) = (1.0 - range, 1.0 + range);
    if v > 0.0 {
        lo = lo.max(b.min / v);
        hi = hi.min(b.max / v);
    }
    [lo, hi]
}

/// The study's directory for a scene: `out/sensitivity/<scene path>`, the scene's path
/// relative to the working directory without its extension, separators as `_`
/// (`scenes/van_air/bump_50mm.toml`: `scenes_van_air_bump_50mm`), so two scenes of one
/// name in different folders keep their own studies. A scene outside the working
/// directory: its stem and 8 hex digits of the FNV-1a of its normalised path.
pub fn default_dir(file: &Path) -> PathBuf {
    use towride_mbs::input::normalized;
    let cwd = std::env::current_dir().unwrap_or_default();
    let full = normalized(&cwd.join(file));
    let name = match full.strip_prefix(normalized(&cwd)) {
        Ok(rel) if !rel.as_os_str().is_empty() => rel
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("_"),
        _ => {
            let stem = file.file_stem().unwrap_or_default().to_string_lossy();
            let h = crate::sweep::fingerprint::fnv1a(full.to_string_lossy().as_bytes());
            format!("{stem}_{:08x}", h as u32)
        }
    };
    PathBuf::from("out").join("sensitivity").join(name)
}
