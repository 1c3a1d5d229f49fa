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
//! A run that fails is recorded with its parameter values and error; the others go on.

pub mod assumed;
pub mod morris;
pub mod outputs;
pub mod params;
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

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Oat => "OAT elasticities",
            Method::Morris => "Morris elementary effects",
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
    /// Groups searched when `params` is empty (empty: hitch, trailer, tyres).
    pub groups: Vec<String>,
    /// Outputs (empty: the defaults of [`outputs::defaults`]).
    pub outputs: Vec<String>,
    /// OAT or Morris.
    pub method: Method,
    /// Morris trajectories.
    pub trajectories: usize,
    /// Morris levels (even).
    pub levels: usize,
    /// Morris range: each value times 1 -+ this.
    pub range: f64,
    /// Morris seed.
    pub seed: u64,
    /// Parallel runs.
    pub jobs: usize,
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
}

/// One parameter's results, per output in `Study::outputs` order.
#[derive(Clone, Debug, Serialize)]
pub struct ParamResult {
    /// The parameter.
    pub param: Param,
    /// OAT elasticities d ln y / d ln p (`None`: a run failed or y <= 0).
    pub elasticity: Vec<Option<f64>>,
    /// Morris statistics.
    pub morris: Vec<morris::Effects>,
    /// Morris mu* relative to the base output.
    pub mu_star_rel: Vec<f64>,
    /// Morris range of the scale factor [low, high].
    pub range: [f64; 2],
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
    /// The scene or mechanism.
    pub file: String,
    /// OAT or Morris.
    pub method: Method,
    /// The outputs.
    pub outputs: Vec<OutputInfo>,
    /// The parameters studied.
    pub params: Vec<ParamResult>,
    /// Values found but dropped: the model does not depend on them.
    pub inactive: Vec<String>,
    /// Runs that failed.
    pub failed: Vec<FailedRun>,
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
    /// Parameters ranked by the first output's |elasticity| (OAT) or mu* (Morris),
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

/// The parameters of `s`: named, or discovered and filtered for activity.
pub fn parameters(s: &Settings) -> Result<(Vec<Param>, Vec<String>)> {
    let all = params::candidates(&s.file, &[])?;
    if !s.params.is_empty() {
        return Ok((params::named(&all, &s.params)?, Vec::new()));
    }
    let groups: Vec<String> = if s.groups.is_empty() {
        ["hitch", "trailer", "tyres"].map(String::from).to_vec()
    } else {
        s.groups.clone()
    };
    let found: Vec<Param> = all
        .into_iter()
        .filter(|p| groups.contains(&p.group))
        .collect();
    if found.is_empty() {
        return Err(towride_mbs::input::InputError {
            file: "command line".into(),
            line: None,
            column: None,
            field: "--group".into(),
            message: format!(
                "no stiffness, damping or mass value in the groups {groups:?} of {}",
                s.file.display()
            ),
            kind: Default::default(),
        }
        .into());
    }
    // Active: a 10 % change alters the assembled model.
    let print = |ov: Vec<Override>| -> Option<String> {
        Job::from_file(&s.file, &Loader::with_overrides(ov))
            .ok()
            .map(|j| format!("{:?}", j.system.model))
    };
    let base = print(Vec::new());
    let pool = pool(s.jobs)?;
    let active: Vec<bool> = pool.install(|| {
        found
            .par_iter()
            .map(|p| base.is_none() || print(vec![p.scaled(1.1)]) != base)
            .collect()
    });
    let mut keep = Vec::new();
    let mut inactive = Vec::new();
    for (p, a) in found.into_iter().zip(active) {
        if a {
            keep.push(p);
        } else {
            inactive.push(p.name);
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

/// One run's outputs, or why it failed.
type Outcome = std::result::Result<Vec<f64>, String>;

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
                    return Err("not run: the study was interrupted".to_string());
                }
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
                    || -> Result<Vec<f64>> {
                        let job = Job::from_file(&s.file, &Loader::with_overrides(ov.clone()))?
                            .without_view();
                        let r = job.run(&StopOnly(progress))?;
                        r.require_completed()?;
                        outputs::evaluate(specs, &r)
                    },
                ));
                progress.inc(1);
                match r {
                    Ok(Ok(v)) => Ok(v),
                    Ok(Err(e)) => Err(e.to_string()),
                    Err(_) => Err("internal error (panic) in the run".to_string()),
                }
            })
            .collect()
    });
    progress.finish();
    Ok(out)
}

/// Runs the study `s`.
pub fn run(s: &Settings, progress: &dyn Progress) -> Result<Study> {
    let wall = Instant::now();
    let (params, inactive) = parameters(s)?;
    let base_job = Job::from_file(&s.file, &Loader::new())?;
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
            let d = morris::design(k, s.trajectories.max(2), s.levels.max(2), s.seed);
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
        .filter_map(|(r, l)| {
            r.as_ref().err().map(|e| FailedRun {
                changes: l.clone(),
                error: e.clone(),
            })
        })
        .collect();
    let base = match &res[0] {
        Ok(v) => v.clone(),
        Err(e) => {
            return Err(crate::scene::SceneError::RunFailed {
                name: format!("{} (the study's base run)", s.file.display()),
                t: 0.0,
                message: e.clone(),
            }
            .into())
        }
    };
    let outputs: Vec<OutputInfo> = specs
        .iter()
        .zip(&base)
        .map(|(o, b)| OutputInfo {
            name: o.name(),
            unit: o.unit.clone(),
            base: *b,
        })
        .collect();
    let no = outputs.len();
    let at = |i: usize, o: usize| res[i].as_ref().ok().map(|v| v[o]);
    let mut results: Vec<ParamResult> = params
        .iter()
        .zip(&ranges)
        .map(|(p, r)| ParamResult {
            param: p.clone(),
            elasticity: Vec::new(),
            morris: Vec::new(),
            mu_star_rel: Vec::new(),
            range: *r,
        })
        .collect();
    match s.method {
        Method::Oat => {
            let dl = 1.1f64.ln() - 0.9f64.ln();
            for (j, pr) in results.iter_mut().enumerate() {
                pr.elasticity = (0..no)
                    .map(|o| match (at(1 + 2 * j, o), at(2 + 2 * j, o)) {
                        (Some(a), Some(b)) if a > 0.0 && b > 0.0 => Some((b.ln() - a.ln()) / dl),
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
                    pr.mu_star_rel.push(e.mu_star / outputs[o].base.abs());
                    pr.morris.push(e);
                }
            }
        }
    }
    Ok(Study {
        schema_version: SCHEMA_VERSION,
        file: s.file.display().to_string(),
        method: s.method,
        outputs,
        params: results,
        inactive,
        failed,
        runs: cases.len(),
        jobs: s.jobs,
        trajectories: if s.method == Method::Morris {
            s.trajectories.max(2)
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

/// The study's directory for a scene: `out/sensitivity/<scene stem>`.
pub fn default_dir(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    PathBuf::from("out").join("sensitivity").join(stem)
}
