//! Calibration: property values fitted so the simulated runs match recorded ones
//! (`towride calibrate`, docs/calibration.md).
//!
//! The steps, each in its module:
//! 1. every recorded run is validated with the model as the files give it and kept as a
//!    [`target::Target`]: its aligned, band-limited curves and a noise weight per channel;
//! 2. the candidate values ([`params`]: named with bounds, or `auto`: the scene's
//!    assumed stiffness, damping and mass values and its obstacle geometry) are ranked
//!    by their effect on the recorded channels and the identifiable ones kept
//!    ([`identify`], Brun et al. 2001); the others stay at their file values, listed
//!    with the reason;
//! 3. a capped global stage (a Latin hypercube over the bounds plus the file values)
//!    picks starting points and Levenberg-Marquardt ([`fit`]) fits from the best few,
//!    each run's time shift fitted beside the values (a nuisance value);
//! 4. the fitted values get intervals and correlations from the final sensitivities and
//!    residual, and every fitted and held-out run is validated before and after.
//!
//! Nothing here prints or draws; [`output`] writes the override file and the report.

pub mod features;
pub mod fit;
pub mod identify;
pub mod output;
pub mod params;
pub mod target;

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::validate::{simulator_with, validate_run, Options};
use fit::{local_fit, Evaluator, LocalFit};
use identify::{select, statistics, Z95};
use params::ParamSpec;
use target::{Band, Residual, Target};
use towride_mbs::input::{Loader, Override};

/// Version of the result document.
pub const SCHEMA_VERSION: u32 = 1;

/// Which values to fit.
#[derive(Clone, Debug)]
pub enum Choice {
    /// `FILE:PATH[=LO..HI],...` as given.
    Listed(String),
    /// The scene's assumed values and obstacle geometry, at most this many kept.
    Auto(usize),
}

/// Settings of a calibration.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The values.
    pub choice: Choice,
    /// Channels fitted (empty: every channel with a signal).
    pub channels: Vec<String>,
    /// Band applied to measured and simulated curves.
    pub band: Option<Band>,
    /// What the residual is made of.
    pub residual: Residual,
    /// Latin-hypercube points of the global stage.
    pub starts: usize,
    /// Local fits from the best points.
    pub local_fits: usize,
    /// Residual evaluations a local fit may make (besides its Jacobians).
    pub max_evaluations: usize,
    /// Seed of the hypercube.
    pub seed: u64,
    /// The comparison's settings (as `validate`).
    pub validate: Options,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            choice: Choice::Auto(6),
            channels: Vec::new(),
            band: None,
            residual: Residual::History,
            starts: 8,
            local_fits: 2,
            max_evaluations: 40,
            seed: 1,
            validate: Options::default(),
        }
    }
}

/// A fitted value with its interval.
#[derive(Clone, Debug, Serialize)]
pub struct Fitted {
    /// The value's description and bounds.
    #[serde(flatten)]
    pub spec: ParamSpec,
    /// The fitted value.
    pub value: f64,
    /// 95 % interval [lo, hi].
    pub interval: [f64; 2],
    /// Standard deviation in the fit's scale (ln x for a positive value).
    pub sd_scale: f64,
    /// The value sits within 1 % of the bounds' width from a bound.
    pub at_bound: bool,
}

/// One run's rating before and after.
#[derive(Clone, Debug, Serialize)]
pub struct Rated {
    /// Run name.
    pub name: String,
    /// Descriptor.
    pub descriptor: String,
    /// Mean rating with the files' values (`validate`'s primary comparison).
    pub before: f64,
    /// With the fitted values.
    pub after: f64,
    /// Peak ratio measured / simulated per channel after the fit.
    pub peak_ratio_after: Vec<(String, f64)>,
    /// Peak ratio before.
    pub peak_ratio_before: Vec<(String, f64)>,
}

/// Curves of one fitted run for the report: measured, start and fitted.
#[derive(Clone, Debug)]
pub struct Overlay {
    /// Run name.
    pub run: String,
    /// Channel names.
    pub channels: Vec<String>,
    /// Sample times [s].
    pub time_s: Vec<f64>,
    /// Measured, per channel.
    pub measured: Vec<Vec<f64>>,
    /// With the files' values.
    pub start: Vec<Vec<f64>>,
    /// With the fitted values.
    pub fitted: Vec<Vec<f64>>,
}

/// The outcome.
#[derive(Clone, Debug, Serialize)]
pub struct Calibration {
    /// Version of this document.
    pub schema_version: u32,
    /// Runs fitted.
    pub targets: Vec<Target>,
    /// The candidates considered (bounds, file values, sources).
    pub candidates: Vec<ParamSpec>,
    /// The values fitted.
    pub fitted: Vec<Fitted>,
    /// Candidates left at their file values, with the reason.
    pub left: Vec<(String, String)>,
    /// Correlation matrix of the fitted values.
    pub correlation: Vec<Vec<f64>>,
    /// Brun et al.'s collinearity index of the fitted set.
    pub collinearity_index: f64,
    /// Singular values of the normalised sensitivity matrix at the fit.
    pub singular_values: Vec<f64>,
    /// Residual RMS (in noise units) at the file values and at the fit.
    pub rms_start: f64,
    /// At the fit.
    pub rms_fitted: f64,
    /// Global stage: (values, cost) of each point tried.
    pub global: Vec<(Vec<f64>, f64)>,
    /// The local fits (the best first).
    pub local_fits: Vec<LocalFit>,
    /// The local fits agree within the intervals (`None` with one fit).
    pub fits_agree: Option<bool>,
    /// Each run's fitted time shift on top of `validate`'s alignment and its standard
    /// deviation [s].
    pub time_shifts: Vec<(String, f64, f64)>,
    /// Fitted runs before and after.
    pub fitted_runs: Vec<Rated>,
    /// Held-out runs before and after.
    pub holdout_runs: Vec<Rated>,
    /// Simulations made and failed.
    pub simulations: usize,
    /// Failed simulations (penalised).
    pub failed_simulations: usize,
    /// Warnings about the result.
    pub warnings: Vec<String>,
    /// Wall time [s].
    pub wall_s: f64,
    /// Curves for the report.
    #[serde(skip)]
    pub overlays: Vec<Overlay>,
}

/// Calibrates the model read with the caller's `base` overrides on the recorded
/// `runs`, checking it on `holdout`; `progress(stage, simulations)` is called as the
/// work goes on.
pub fn calibrate(
    runs: &[PathBuf],
    holdout: &[PathBuf],
    base: &[Override],
    settings: &Settings,
    progress: &(dyn Fn(&str, usize) + Sync),
) -> Result<Calibration, crate::Error> {
    let wall = Instant::now();
    // The values first: a misspelt one is refused before any simulation.
    let first = runs.first().ok_or_else(|| {
        crate::validate::ValidateError::Signal("give at least one recorded run".into())
    })?;
    let scene = crate::validate::Descriptor::from_file(first)?.scene;
    let (candidates, refused) = match &settings.choice {
        Choice::Listed(list) => (params::parse(list, &scene)?, Vec::new()),
        Choice::Auto(_) => output::auto_candidates(&scene)?,
    };
    let loader = Loader::with_overrides(base.to_vec());
    progress("aligning the recorded runs", 0);
    let prepared: Vec<_> = runs
        .par_iter()
        .map(|r| {
            target::Target::prepare(
                r,
                &loader,
                &settings.channels,
                settings.band,
                settings.residual,
                &settings.validate,
            )
        })
        .collect::<Result<_, _>>()?;
    let (targets, before): (Vec<Target>, Vec<_>) = prepared.into_iter().unzip();
    let max_kept = match settings.choice {
        Choice::Auto(n) => n,
        Choice::Listed(_) => candidates.len(),
    };
    let stage = std::sync::Mutex::new("ranking the values".to_string());
    let tick = |n: usize| {
        if let Ok(s) = stage.lock() {
            progress(&s, n);
        }
    };
    let set_stage = |s: &str| {
        if let Ok(mut g) = stage.lock() {
            *g = s.to_string();
        }
    };
    // Rank and select at the file values.
    let all = Evaluator::new(&targets, &candidates, base.to_vec(), &tick);
    let x_file: Vec<f64> = candidates.iter().map(|c| c.file_value).collect();
    // The start must simulate: its error, if any, is the user's to see.
    for t in &targets {
        t.simulate(&all.loader(&x_file), 0.0)?;
    }
    let r0 = all.residuals(&x_file).ok_or_else(|| {
        crate::validate::ValidateError::Signal(
            "the model with the files' values does not simulate every run".into(),
        )
    })?;
    let cost0 = 0.5 * r0.iter().map(|v| v * v).sum::<f64>();
    let j0 = all.jacobian_scale(&x_file, &r0);
    let l = targets
        .iter()
        .map(Target::samples_per_independent)
        .fold(1.0, f64::max);
    let names: Vec<String> = candidates.iter().map(|c| c.name.clone()).collect();
    let log: Vec<bool> = candidates.iter().map(|c| c.log).collect();
    let widths: Vec<f64> = candidates.iter().map(ParamSpec::scale_per_u).collect();
    let sel = select(&j0, &names, &log, &widths, l, max_kept);
    let mut simulations = all.simulations.load(std::sync::atomic::Ordering::Relaxed);
    let mut failed = all.failures.load(std::sync::atomic::Ordering::Relaxed);
    let mut left: Vec<(String, String)> = sel
        .left
        .iter()
        .map(|x| (names[x.index].clone(), x.reason.clone()))
        .collect();
    left.extend(refused);
    if sel.kept.is_empty() {
        return Err(crate::validate::ValidateError::Signal(format!(
            "none of the {} values can be pinned down by these recordings: {}",
            candidates.len(),
            left.iter()
                .map(|(n, r)| format!("{n}: {r}"))
                .collect::<Vec<_>>()
                .join("; ")
        ))
        .into());
    }
    // The kept values, then each run's time shift.
    let n = sel.kept.len();
    let mut specs: Vec<ParamSpec> = sel.kept.iter().map(|&i| candidates[i].clone()).collect();
    if settings.residual != Residual::Features {
        specs.extend(
            targets
                .iter()
                .enumerate()
                .map(|(k, t)| ParamSpec::time_shift(k, &t.name, settings.validate.max_shift_s)),
        );
    }
    let start: Vec<f64> = specs.iter().map(|s| s.file_value).collect();

    // Global stage: the file values and a Latin hypercube; local fits from the best.
    set_stage("global stage");
    let ev = Evaluator::new(&targets, &specs, base.to_vec(), &tick);
    ev.set_penalty(cost0);
    let mut points = vec![start.clone()];
    points.extend(output::hypercube(&specs, settings.starts, settings.seed));
    let costs: Vec<f64> = points
        .par_iter()
        .map(|x| {
            ev.residuals(x).map_or(f64::INFINITY, |r| {
                0.5 * r.iter().map(|v| v * v).sum::<f64>()
            })
        })
        .collect();
    let global: Vec<(Vec<f64>, f64)> = points.iter().cloned().zip(costs.iter().copied()).collect();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    let mut fits: Vec<LocalFit> = Vec::new();
    for (i, &p) in order.iter().take(settings.local_fits.max(1)).enumerate() {
        set_stage(&format!(
            "local fit {} of {}",
            i + 1,
            settings.local_fits.max(1)
        ));
        fits.push(local_fit(&ev, &points[p], settings.max_evaluations));
    }
    fits.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let best = fits[0].values.clone();

    // Intervals and correlations at the fit (same evaluator: its counts go on).
    set_stage("intervals");
    let r_fit = ev.residuals(&best).unwrap_or_default();
    let j_fit = ev.jacobian_scale(&best, &r_fit);
    let m = r_fit.len();
    let ssr: f64 = r_fit.iter().map(|v| v * v).sum();
    let s2 = ssr / (m.saturating_sub(specs.len())).max(1) as f64;
    // The shifts stay in the covariance: a value correlated with a shift is as uncertain
    // as the shift leaves it.
    let cols: Vec<usize> = (0..specs.len()).collect();
    let st = statistics(&j_fit, &cols, s2, l);
    simulations += ev.simulations.load(std::sync::atomic::Ordering::Relaxed);
    failed += ev.failures.load(std::sync::atomic::Ordering::Relaxed);
    let mut warnings = Vec::new();
    let sd: Vec<f64> = match &st {
        Some(s) => s.sd_scale.clone(),
        None => {
            warnings.push("the sensitivities at the fit are singular: no intervals".into());
            vec![f64::NAN; specs.len()]
        }
    };
    let time_shifts: Vec<(String, f64, f64)> = (n..specs.len())
        .map(|j| (targets[j - n].name.clone(), best[j], sd[j]))
        .collect();
    let fitted: Vec<Fitted> = specs[..n]
        .iter()
        .zip(&best)
        .zip(&sd)
        .map(|((s, &x), &sd)| {
            let c = s.scale(x);
            let u = s.coordinate(x);
            Fitted {
                spec: s.clone(),
                value: x,
                interval: [s.unscale(c - Z95 * sd), s.unscale(c + Z95 * sd)],
                sd_scale: sd,
                at_bound: !(0.01..=0.99).contains(&u),
            }
        })
        .collect();
    for f in fitted.iter().filter(|f| f.at_bound) {
        warnings.push(format!(
            "{} ends at its bound ({}): the recordings want a value outside {}..{}",
            f.spec.name, f.value, f.spec.lo, f.spec.hi
        ));
    }
    if let Some(s) = &st {
        for a in 0..specs.len() {
            for b in 0..a {
                if s.correlation[a][b].abs() > identify::MAX_CORRELATION {
                    warnings.push(format!(
                        "at the fit {} and {} are correlated {:.2}: their sum or ratio is pinned down, not each",
                        specs[a].name, specs[b].name, s.correlation[a][b]
                    ));
                }
            }
        }
    }
    let fits_agree = (fits.len() > 1).then(|| {
        fits[1..].iter().all(|f| {
            (0..n).all(|j| {
                let d = (specs[j].scale(f.values[j]) - specs[j].scale(best[j])).abs();
                d <= Z95 * sd[j] || !sd[j].is_finite()
            })
        })
    });
    if fits_agree == Some(false) {
        warnings.push(
            "the local fits end at different values (beyond the intervals): the cost has more than one minimum in the bounds".into(),
        );
    }

    // Ratings before and after, fitted and held-out runs.
    set_stage("rating");
    let fitted_loader = ev.loader(&best);
    let rate = |paths: &[PathBuf], before: Option<&[crate::validate::RunValidation]>| {
        paths
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let b = match before {
                    Some(v) => v[i].clone(),
                    None => validate_run(
                        p,
                        simulator_with(loader.clone()).as_ref(),
                        &settings.validate,
                    )?,
                };
                let a = validate_run(
                    p,
                    simulator_with(fitted_loader.clone()).as_ref(),
                    &settings.validate,
                )?;
                Ok(output::rated(&b, &a))
            })
            .collect::<Result<Vec<Rated>, crate::Error>>()
    };
    let fitted_runs = rate(runs, Some(&before))?;
    let holdout_runs = rate(holdout, None)?;
    progress("done", simulations);
    let shifts: Vec<f64> = time_shifts.iter().map(|s| s.1).collect();
    let overlays = output::overlays(&targets, &all_loaders(&ev, &start, &best), &shifts);
    Ok(Calibration {
        schema_version: SCHEMA_VERSION,
        rms_start: (2.0 * cost0 / r0.len().max(1) as f64).sqrt(),
        rms_fitted: (ssr / m.max(1) as f64).sqrt(),
        targets,
        candidates,
        fitted,
        left,
        correlation: st
            .as_ref()
            .map(|s| s.correlation[..n].iter().map(|r| r[..n].to_vec()).collect())
            .unwrap_or_default(),
        time_shifts,
        collinearity_index: st.as_ref().map_or(f64::NAN, |s| s.collinearity_index),
        singular_values: st.map(|s| s.singular_values).unwrap_or_default(),
        global,
        local_fits: fits,
        fits_agree,
        fitted_runs,
        holdout_runs,
        simulations,
        failed_simulations: failed,
        warnings,
        wall_s: wall.elapsed().as_secs_f64(),
        overlays,
    })
}

fn all_loaders(ev: &Evaluator, start: &[f64], best: &[f64]) -> [Loader; 2] {
    [ev.loader(start), ev.loader(best)]
}
