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
pub mod settings;
pub mod study;
pub mod tornado;
pub mod write;

use std::time::Instant;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::job::Job;
pub use outputs::OutputSpec;
pub use params::Param;
use settings::{check_settings, range_of};
pub use settings::{
    default_dir, Method, Settings, DEFAULT_GROUPS, MAX_TRAJECTORIES, MIN_TRAJECTORIES,
};
use study::verdict;
pub use study::{FailedRun, OutputInfo, ParamResult, Study};
use towride_mbs::input::Override;
use towride_mbs::progress::Progress;

/// Version of the study's JSON layout. 2: outputs `CHANNEL.abs_peak`, `.max`, `.min`
/// (`.peak` and `.peak100` are gone; band-limited channels by their own names). 3: each
/// output's `base_signed` (an `.abs_peak`'s signed sample) and elasticities of negative
/// outputs.
pub const SCHEMA_VERSION: u32 = 3;

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
        .filter(|p| groups.contains(&p.group) && !params::driven_by_factors(p, &all))
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
