//! The least-squares fit: residuals of every target at a parameter set (the targets'
//! simulations in parallel), finite-difference sensitivities (one simulation per value
//! and target, all in parallel), and MINPACK's Levenberg-Marquardt (the
//! `levenberg-marquardt` crate, a port of Moré's lmder) on the bounded variables of
//! [`super::params`].
//!
//! A simulation that fails inside the loop is a penalty, not an abort: its residuals
//! are set so the cost is [`PENALTY_FACTOR`] times the starting cost, so the trust
//! region shrinks away from it; the count of failures is reported.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{storage::Owned, DMatrix, DVector, Dyn};
use rayon::prelude::*;

use super::params::{bounded, ParamSpec};
use super::target::Target;
use towride_mbs::input::{Loader, Override};

/// A failed simulation costs this many times the cost at the start.
pub const PENALTY_FACTOR: f64 = 100.0;
/// Step of the finite differences in the bounded coordinate u (a share of the bounds'
/// width in the fit's scale): about 1 % of the value for bounds of a factor 2 either
/// side. Large against the integrator's tolerance noise (relative 1e-4 at most on the
/// curves), small against the curvature over the bounds.
pub const FD_STEP_U: f64 = 0.01;

/// Everything an evaluation needs; shared by the threads.
pub struct Evaluator<'a> {
    /// The runs fitted.
    pub targets: &'a [Target],
    /// The values fitted (property values, then any time shifts).
    pub specs: &'a [ParamSpec],
    /// The caller's overrides (under the fitted values).
    pub base: Vec<Override>,
    /// Simulations made.
    pub simulations: AtomicUsize,
    /// Simulations that failed.
    pub failures: AtomicUsize,
    /// Residual length of a failed evaluation's penalty, set once the start is known.
    penalty: Mutex<f64>,
    /// Cost (0.5 |r|^2) of every residual evaluation, in order.
    pub history: Mutex<Vec<f64>>,
    /// Called after every simulation with the count so far.
    pub tick: &'a (dyn Fn(usize) + Sync),
}

impl<'a> Evaluator<'a> {
    /// An evaluator of `targets` over `specs`.
    pub fn new(
        targets: &'a [Target],
        specs: &'a [ParamSpec],
        base: Vec<Override>,
        tick: &'a (dyn Fn(usize) + Sync),
    ) -> Evaluator<'a> {
        Evaluator {
            targets,
            specs,
            base,
            simulations: AtomicUsize::new(0),
            failures: AtomicUsize::new(0),
            penalty: Mutex::new(f64::NAN),
            history: Mutex::new(Vec::new()),
            tick,
        }
    }

    /// Number of residuals.
    pub fn len(&self) -> usize {
        self.targets.iter().map(Target::len).sum()
    }

    /// No residuals.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The loader of the model at values `x`.
    pub fn loader(&self, x: &[f64]) -> Loader {
        let mut all = self.base.clone();
        all.extend(
            self.specs
                .iter()
                .zip(x)
                .filter(|(s, _)| s.shift_of.is_none())
                .map(|(s, v)| s.override_for(*v)),
        );
        Loader::with_overrides(all)
    }

    /// One target simulated at `x`: its residuals, or `None` when the simulation failed.
    fn target_residual(&self, k: usize, x: &[f64]) -> Option<Vec<f64>> {
        let t = &self.targets[k];
        let shift = self
            .specs
            .iter()
            .zip(x)
            .find(|(s, _)| s.shift_of == Some(k))
            .map_or(0.0, |(_, v)| *v);
        let r = t
            .simulate(&self.loader(x), shift)
            .ok()
            .map(|s| t.residual(s));
        let n = self.simulations.fetch_add(1, Ordering::Relaxed) + 1;
        if r.is_none() {
            self.failures.fetch_add(1, Ordering::Relaxed);
        }
        (self.tick)(n);
        r
    }

    /// Residuals of every target at `x` (in parallel); a failed target's part is the
    /// penalty (or `None` before the penalty is set: the start must simulate).
    pub fn residuals(&self, x: &[f64]) -> Option<Vec<f64>> {
        let parts: Vec<Option<Vec<f64>>> = (0..self.targets.len())
            .into_par_iter()
            .map(|k| self.target_residual(k, x))
            .collect();
        let penalty = *self.penalty.lock().ok()?;
        let mut r = Vec::with_capacity(self.len());
        for (p, t) in parts.into_iter().zip(self.targets) {
            match p {
                Some(v) => r.extend(v),
                None if penalty.is_finite() => r.extend(std::iter::repeat_n(penalty, t.len())),
                None => return None,
            }
        }
        if let Ok(mut h) = self.history.lock() {
            h.push(0.5 * r.iter().map(|v| v * v).sum::<f64>());
        }
        Some(r)
    }

    /// Fixes the penalty from the starting cost.
    pub fn set_penalty(&self, start_cost: f64) {
        let m = self.len().max(1) as f64;
        if let Ok(mut p) = self.penalty.lock() {
            *p = (2.0 * PENALTY_FACTOR * start_cost.max(1.0) / m).sqrt();
        }
    }

    /// d r / d s (s the fit's scale of each value) at `x` by forward differences in u,
    /// one simulation per value and target, all in parallel; `r0` the residuals at `x`.
    /// A column whose step fails is tried backwards; failing both it is zero.
    pub fn jacobian_scale(&self, x: &[f64], r0: &[f64]) -> DMatrix<f64> {
        let n = self.specs.len();
        let offsets: Vec<usize> = self
            .targets
            .iter()
            .scan(0, |acc, t| {
                let o = *acc;
                *acc += t.len();
                Some(o)
            })
            .collect();
        // A run's time shift moves that run's residuals only.
        let jobs: Vec<(usize, usize)> = (0..n)
            .flat_map(|j| (0..self.targets.len()).map(move |k| (j, k)))
            .filter(|&(j, k)| self.specs[j].shift_of.is_none_or(|o| o == k))
            .collect();
        let cols: Vec<(usize, usize, Option<Vec<f64>>)> = jobs
            .par_iter()
            .map(|&(j, k)| {
                let s = &self.specs[j];
                let u = s.coordinate(x[j]);
                let t = &self.targets[k];
                let try_step = |du: f64| {
                    let mut xp = x.to_vec();
                    xp[j] = s.value(u + du);
                    let ds = s.scale(xp[j]) - s.scale(x[j]);
                    self.target_residual(k, &xp).map(|r| {
                        let r0 = &r0[offsets[k]..offsets[k] + t.len()];
                        r.iter().zip(r0).map(|(a, b)| (a - b) / ds).collect()
                    })
                };
                // Step inwards at the upper bound.
                let du = if u + FD_STEP_U <= 1.0 {
                    FD_STEP_U
                } else {
                    -FD_STEP_U
                };
                let col = try_step(du).or_else(|| try_step(-du));
                (j, k, col)
            })
            .collect();
        let mut jac = DMatrix::zeros(r0.len(), n);
        for (j, k, col) in cols {
            if let Some(c) = col {
                for (i, v) in c.into_iter().enumerate() {
                    jac[(offsets[k] + i, j)] = v;
                }
            }
        }
        jac
    }
}

/// The values at the least-squares variables `z`.
pub fn values(specs: &[ParamSpec], z: &[f64]) -> Vec<f64> {
    specs
        .iter()
        .zip(z)
        .map(|(s, &zi)| s.value(bounded(zi).0))
        .collect()
}

/// The problem the LM driver sees: variables z, residuals cached per point.
struct Problem<'e, 'a> {
    ev: &'e Evaluator<'a>,
    z: DVector<f64>,
    r: Option<DVector<f64>>,
    /// The last few points evaluated (the driver resets to the best point at the end).
    memo: VecDeque<(DVector<f64>, Option<DVector<f64>>)>,
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, '_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, z: &DVector<f64>) {
        self.z = z.clone();
        if let Some((_, r)) = self.memo.iter().find(|(p, _)| p == z) {
            self.r = r.clone();
            return;
        }
        let x = values(self.ev.specs, z.as_slice());
        self.r = self.ev.residuals(&x).map(DVector::from_vec);
        self.memo.push_back((z.clone(), self.r.clone()));
        if self.memo.len() > 4 {
            self.memo.pop_front();
        }
    }

    fn params(&self) -> DVector<f64> {
        self.z.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.r.clone()
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = self.r.as_ref()?;
        let x = values(self.ev.specs, self.z.as_slice());
        let js = self.ev.jacobian_scale(&x, r0.as_slice());
        // Chain rule: ds/dz = ds/du du/dz.
        let mut jz = js;
        for (j, s) in self.ev.specs.iter().enumerate() {
            let (_, du_dz) = bounded(self.z[j]);
            let f = s.scale_per_u() * du_dz;
            jz.column_mut(j).scale_mut(f);
        }
        Some(jz)
    }
}

/// One local fit's outcome.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LocalFit {
    /// Starting values.
    pub start: Vec<f64>,
    /// Fitted values.
    pub values: Vec<f64>,
    /// Cost at the start and the end (0.5 sum of squared normalised residuals).
    pub start_cost: f64,
    /// Cost at the end.
    pub cost: f64,
    /// Why the driver stopped.
    pub termination: String,
    /// The driver's residual evaluations.
    pub evaluations: usize,
    /// Cost of every evaluation of this fit, in order.
    pub cost_history: Vec<f64>,
}

/// Levenberg-Marquardt from `start` (values), at most `max_evaluations` residual
/// evaluations besides the Jacobians.
pub fn local_fit(ev: &Evaluator, start: &[f64], max_evaluations: usize) -> LocalFit {
    let z0: Vec<f64> = ev
        .specs
        .iter()
        .zip(start)
        .map(|(s, &x)| super::params::unbounded(s.coordinate(x)))
        .collect();
    let first = ev.history.lock().map_or(0, |h| h.len());
    let mut p = Problem {
        ev,
        z: DVector::from_vec(z0.clone()),
        r: None,
        memo: VecDeque::new(),
    };
    p.set_params(&DVector::from_vec(z0));
    let start_cost =
        p.r.as_ref()
            .map_or(f64::INFINITY, |r| 0.5 * r.norm_squared());
    let n = ev.specs.len().max(1);
    // The simulations agree with themselves to about 1e-5 relative: tighter tolerances
    // would only chase that noise.
    let lm = LevenbergMarquardt::new()
        .with_ftol(1e-5)
        .with_xtol(1e-5)
        .with_gtol(1e-10)
        .with_patience(max_evaluations.div_ceil(n + 1).max(1));
    let (p, report) = lm.minimize(p);
    let cost =
        p.r.as_ref()
            .map_or(f64::INFINITY, |r| 0.5 * r.norm_squared());
    let history = ev
        .history
        .lock()
        .map(|h| h[first..].to_vec())
        .unwrap_or_default();
    LocalFit {
        start: start.to_vec(),
        values: values(ev.specs, p.z.as_slice()),
        start_cost,
        cost,
        termination: format!("{:?}", report.termination),
        evaluations: report.number_of_evaluations,
        cost_history: history,
    }
}
