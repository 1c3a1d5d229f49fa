//! The robustness of a study's ranking ([`super::robust`]): the sweep's grid (or the
//! block's subset of it) run again with each moved value at each end of its range, each
//! such run a sweep of its own in `OUT/robustness/<NN>_<low|high>/` (parallel,
//! resumable and fingerprinted as any sweep: the moved value is one of its overrides),
//! and each ranking ([`super::rank`], the variants by each figure's mean over the grid)
//! compared with the nominal one over the same cases:
//!
//! - Kendall's tau-b of the perturbed means against the nominal means over the ranked
//!   values both have (Kendall 1945, "The treatment of ties in ranking problems",
//!   Biometrika 33(3); tau_b = (P - Q) / sqrt((P + Q + T)(P + Q + U)) with P, Q the
//!   concordant and discordant pairs, T and U the pairs tied in one ranking only, as
//!   scipy.stats.kendalltau defines it; computed by the `kendalls` crate, Knight's
//!   O(n log n) method). 1: same order; -1: reversed; `None` where every value ties.
//! - The best value of each, whether the nominal best stays best, and whether it stays
//!   within the spread: its perturbed mean no larger than the largest figure the
//!   perturbed best shows over the grid (the difference is smaller than what speed and
//!   load alone move the best by).

use std::cmp::Ordering;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::exec::{run_sweep_with, Options};
use super::page::{read, Table};
use super::rank::{rank, Ranking};
use super::robust::Robustness;
use super::{Parameter, Sweep};
use crate::error::Result;
use towride_mbs::input::InputError;
use towride_mbs::progress::Progress;

/// One figure's ranking under one perturbation against the nominal one.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Outcome {
    /// The figure, `hitch_fx abs_peak [N]`.
    pub figure: String,
    /// Kendall's tau-b against the nominal ranking; `None`: fewer than two values in
    /// common, or every value ties.
    pub tau_b: Option<f64>,
    /// The best value (lowest mean) of the perturbed ranking.
    pub best: String,
    /// The nominal ranking's best value.
    pub nominal_best: String,
    /// Its rank in the perturbed ranking (1: still best).
    pub nominal_best_rank: usize,
    /// True when the nominal best is still best.
    pub stays_best: bool,
    /// True when its perturbed mean is within the perturbed best's spread over the grid.
    pub within_spread: bool,
}

/// One moved value at one end of its range.
#[derive(Clone, Debug, Serialize)]
pub struct Perturbation {
    /// `FILE:PATH`.
    pub parameter: String,
    /// Its source class.
    pub class: String,
    /// "low" or "high".
    pub end: String,
    /// Its scale factor.
    pub factor: f64,
    /// Its value there (the file's value times the factor).
    pub value: f64,
    /// The runs' summary CSV.
    pub summary_csv: Option<String>,
    /// Cases that failed.
    pub failed: usize,
    /// Per figure.
    pub outcomes: Vec<Outcome>,
    /// Why there is no ranking, if so.
    pub note: Option<String>,
}

/// The robustness of the ranking.
#[derive(Clone, Debug, Serialize)]
pub struct RobustnessRun {
    /// "completed", "interrupted" (a perturbed sweep was; `--resume` finishes it) or
    /// "not run" (`note` says why).
    pub status: String,
    /// Why it did not run.
    pub note: Option<String>,
    /// The block.
    pub block: Robustness,
    /// Cases per perturbed sweep.
    pub cases_per_run: usize,
    /// The nominal ranking over the same cases.
    pub nominal: Option<Ranking>,
    /// Each moved value at each end.
    pub perturbations: Vec<Perturbation>,
    /// Wall time of the perturbed sweeps [s].
    pub wall_s: f64,
}

impl RobustnessRun {
    /// The block, not run for `note`'s reason.
    pub fn not_run(block: &Robustness, note: String) -> RobustnessRun {
        RobustnessRun {
            status: "not run".into(),
            note: Some(note),
            block: block.clone(),
            cases_per_run: 0,
            nominal: None,
            perturbations: Vec::new(),
            wall_s: 0.0,
        }
    }
}

/// Compares `perturbed` with `nominal`, figure by figure (the figures both rank).
pub fn compare(nominal: &Ranking, perturbed: &Ranking) -> Vec<Outcome> {
    let mut out = Vec::new();
    for n in &nominal.figures {
        let Some(p) = perturbed.figures.iter().find(|f| f.figure == n.figure) else {
            continue;
        };
        let pairs: Vec<(f64, f64)> = n
            .entries
            .iter()
            .filter_map(|e| {
                let q = p.entries.iter().find(|q| q.value == e.value)?;
                Some((e.mean, q.mean))
            })
            .collect();
        let (x, y): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
        let nb = p.entries.iter().find(|e| e.value == n.best);
        let best = p.entries.iter().find(|e| e.value == p.best);
        out.push(Outcome {
            figure: n.figure.clone(),
            tau_b: tau_b(&x, &y),
            best: p.best.clone(),
            nominal_best: n.best.clone(),
            nominal_best_rank: nb.map_or(0, |e| e.rank),
            stays_best: p.best == n.best,
            within_spread: match (nb, best) {
                (Some(a), Some(b)) => a.mean <= b.max,
                _ => false,
            },
        });
    }
    out
}

/// Kendall's tau-b of `x` and `y` (see the module text); `None` where it is undefined.
pub fn tau_b(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() < 2 {
        return None;
    }
    let cmp = |a: &f64, b: &f64| a.partial_cmp(b).unwrap_or(Ordering::Greater);
    let (t, _) = kendalls::tau_b_with_comparator(x, y, cmp).ok()?;
    t.is_finite().then_some(t)
}

/// The rows of `t` inside `block`'s subset.
fn in_subset(t: &Table, block: &Robustness) -> Table {
    let col = |n: &str| t.parameters.iter().position(|p| p == n);
    let rows = t
        .rows
        .iter()
        .filter(|r| {
            block.subset.iter().all(|(k, vs)| {
                col(k).is_some_and(|c| {
                    let cell = &r.values[c];
                    vs.iter().any(|v| super::usage::same_value(v, cell))
                })
            })
        })
        .cloned()
        .collect();
    Table { rows, ..t.clone() }
}

/// The sweep's parameters with the subset's values in place of theirs.
fn subset_parameters(sweep: &Sweep, block: &Robustness) -> Vec<Parameter> {
    let mut ps = sweep.parameters.clone();
    for p in &mut ps {
        if let Some((_, v)) = block.subset.iter().find(|(k, _)| *k == p.name) {
            p.values = v.clone();
        }
    }
    ps
}

/// A ranking error about the block's `figures`, located there.
fn at_figures(block: &Robustness, message: String) -> crate::Error {
    InputError {
        message,
        ..(*block.figures_at).clone()
    }
    .into()
}

/// Runs the block of `sweep` whose nominal summary is `csv`, the perturbed sweeps in
/// `out/robustness/`, with `opts` (jobs, resume).
pub fn run(
    sweep: &Sweep,
    block: &Robustness,
    csv: &Path,
    out: &Path,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<RobustnessRun> {
    let wall = Instant::now();
    let nominal_table = in_subset(&read(csv)?, block);
    let nominal =
        rank(&nominal_table, &block.by, &block.figures).map_err(|e| at_figures(block, e))?;
    let parameters = subset_parameters(sweep, block);
    let sub_opts = Options {
        keep_histories: false,
        check: None,
        ..*opts
    };
    let mut res = RobustnessRun {
        status: "completed".into(),
        note: None,
        block: block.clone(),
        cases_per_run: parameters.iter().map(|p| p.values.len()).product(),
        nominal: Some(nominal.clone()),
        perturbations: Vec::new(),
        wall_s: 0.0,
    };
    for (k, m) in block.moves.iter().enumerate() {
        for (e, end) in ["low", "high"].into_iter().enumerate() {
            let sub = Sweep {
                name: format!("{}: {} x {:.3}", sweep.name, m.parameter, m.factors[e]),
                parameters: parameters.clone(),
                base: sweep.base.fresh().extended(m.ends[e].clone()),
                usage: None,
                robustness: None,
                ..sweep.clone()
            };
            let dir = out.join("robustness").join(format!("{:02}_{end}", k + 1));
            let r = run_sweep_with(&sub, (0, 1), &dir, &sub_opts, progress)?;
            let mut p = Perturbation {
                parameter: m.parameter.clone(),
                class: m.class.clone(),
                end: end.into(),
                factor: m.factors[e],
                value: m.base * m.factors[e],
                summary_csv: r.summary_csv.clone(),
                failed: r.failed,
                outcomes: Vec::new(),
                note: None,
            };
            if r.interrupted > 0 {
                res.status = "interrupted".into();
                res.perturbations.push(p);
                res.wall_s = wall.elapsed().as_secs_f64();
                return Ok(res);
            }
            let csv = r.summary_csv.as_deref().map(Path::new);
            match csv
                .map(read)
                .transpose()?
                .map(|t| rank(&t, &block.by, &block.figures))
            {
                Some(Ok(ranking)) => p.outcomes = compare(&nominal, &ranking),
                Some(Err(e)) => p.note = Some(e),
                None => p.note = Some("no summary written".into()),
            }
            res.perturbations.push(p);
        }
    }
    res.wall_s = wall.elapsed().as_secs_f64();
    Ok(res)
}
