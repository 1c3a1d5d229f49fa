//! What the integrators share: the method trait [`DaeMethod`] whose driver (to an output
//! time, the stop time, events) is written once on the method's `step` (the pattern of
//! diffsol's `OdeSolverMethod`), the state that driver keeps ([`Core`]), the error weights
//! and the diagnostics. [`crate::Bdf`] and [`crate::Radau5`] differ only in their start,
//! their step and their interpolant.

use std::ops::Range;

use crate::error::SolverError;
use crate::linear::{NewtonMatrix, Singular};
use crate::options::{AlgebraicControl, LinearSolver, SolverOptions, Stats};
use crate::problem::{DaeProblem, VarKind};
use crate::roots::Roots;

/// Convergence failures in one step after which the run ends: IDA's `MXNCF` (`ida.c`),
/// the default of `SolverOptions::max_convergence_failures` (Radau IIA: non-finite
/// residuals only).
pub const MXNCF: usize = 10;
/// Error-test failures in one step after which a BDF run ends: IDA's `MXNEF` (`ida.c`),
/// the default of `SolverOptions::max_error_failures`.
pub const MXNEF: usize = 10;

/// Rounding units (of max(|tstop|, 1)) within which the stop time counts as reached.
pub(crate) const TSTOP_UROUNDS: f64 = 4.0;
/// The first step when the options give none: this fraction of the distance to the first
/// output time (IDASolve: hh = PT001 * tdist) ...
const H0_FRACTION: f64 = 0.001;
/// ... at most H0_NORM / ||y'0|| (IDASolve: HALF / ypnorm).
const H0_NORM: f64 = 0.5;
/// Unknowns named in a diagnostic.
const WORST_SHOWN: usize = 3;
/// Unknowns or equations named in a singular-matrix or non-finite-residual message.
const NAMES_SHOWN: usize = 5;

/// What a call to [`DaeMethod::advance`] ended with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Advance {
    /// The solver's internal time has reached or passed `tout`.
    Reached,
    /// An event function changed sign at `t` (before `tout`); `index` is which one.
    Root {
        /// Time of the sign change, located to within the root tolerance [s].
        t: f64,
        /// Index of the event function that changed sign.
        index: usize,
    },
}

/// The state every method keeps alike: the problem and settings, the time reached, the
/// stop time, the event search and the statistics. Only the methods construct it.
pub struct Core<'a, P: DaeProblem + ?Sized> {
    pub(crate) prob: &'a P,
    pub(crate) opts: SolverOptions,
    pub(crate) n: usize,
    pub(crate) kinds: Vec<VarKind>,
    /// Error control of the algebraic unknowns with `Auto` resolved (`Auto` stays only
    /// for problems of index <= 2, meaning: index-2 unknowns out of the error test).
    pub(crate) algebraic: AlgebraicControl,
    /// Vector-valued unknowns weighted by their length (empty when the option is off).
    pub(crate) groups: Vec<Range<usize>>,
    /// The time reached: the end of the last accepted step (during a step the BDF keeps
    /// its trial time here, as IDA's tn).
    pub(crate) t: f64,
    /// Size of the last accepted step (0 before the first): the interpolant covers
    /// [t - h_used, t].
    pub(crate) h_used: f64,
    pub(crate) started: bool,
    pub(crate) tstop: Option<f64>,
    pub(crate) roots: Roots,
    pub(crate) stats: Stats,
    /// Accepted steps in which each unknown dominated the error estimate.
    limiter_counts: Vec<usize>,
}

impl<'a, P: DaeProblem + ?Sized> Core<'a, P> {
    /// Checks the settings and the start, resolves `Auto` algebraic control and
    /// evaluates the event functions at the start.
    pub(crate) fn new(
        prob: &'a P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: SolverOptions,
    ) -> Result<Self, SolverError> {
        let n = prob.size();
        opts.validate(n)?;
        let kinds = crate::problem::check_start(prob, t0, y0, yp0)?;
        let algebraic = match opts.algebraic {
            AlgebraicControl::Auto if kinds.contains(&VarKind::Index3) => AlgebraicControl::Scaled,
            a => a,
        };
        let mut stats = Stats::default();
        let roots = Roots::new(prob, t0, y0, yp0, &mut stats.root_evals);
        Ok(Self {
            prob,
            n,
            kinds,
            algebraic,
            groups: Vec::new(),
            t: t0,
            h_used: 0.0,
            started: false,
            tstop: None,
            roots,
            stats,
            limiter_counts: vec![0; n],
            opts,
        })
    }

    /// The real iteration matrix for the problem's sparsity pattern: dense LU without a
    /// pattern or, under `LinearSolver::Auto`, below `dense_limit` unknowns.
    pub(crate) fn newton_matrix(&self) -> Result<NewtonMatrix, SolverError> {
        let pattern = self.prob.jacobian_pattern();
        let dense = match self.opts.linear_solver {
            LinearSolver::Dense => true,
            LinearSolver::Sparse => false,
            LinearSolver::Auto => pattern.is_none() || self.n < self.opts.dense_limit,
        };
        NewtonMatrix::new(self.n, pattern, dense)
    }

    /// The first step size: the options' `h_init`, or IDA's rule (IDASolve) from the
    /// weighted norm of the differential unknowns' derivatives; at most `h_max`.
    pub(crate) fn initial_step(&self, tout: f64, yp: &[f64], ewt: &[f64]) -> f64 {
        let h = match self.opts.h_init {
            Some(h) => h,
            None => {
                let mut h = H0_FRACTION * (tout - self.t).abs();
                let mut sum = 0.0;
                for i in 0..self.n {
                    if self.kinds[i] == VarKind::Differential {
                        sum += (yp[i] * ewt[i]).powi(2);
                    }
                }
                let ypnorm = (sum / self.n as f64).sqrt();
                if ypnorm > H0_NORM / h {
                    h = H0_NORM / ypnorm;
                }
                h
            }
        };
        h.min(self.opts.h_max)
    }

    /// `t`, or the stop time when `t` is within round-off of it.
    pub(crate) fn snap_to_stop(&self, t: f64) -> f64 {
        match self.tstop {
            Some(ts) if (t - ts).abs() <= TSTOP_UROUNDS * f64::EPSILON * ts.abs().max(1.0) => ts,
            _ => t,
        }
    }

    /// Books an accepted step of size `h` and `order` ending at `t`; `err` weighted by `w`
    /// is its error estimate (for the step limiters).
    pub(crate) fn book_step(&mut self, h: f64, order: usize, err: &[f64], w: &[f64]) {
        self.stats.steps += 1;
        self.h_used = h;
        self.stats.last_order = order;
        self.stats.last_step = h;
        self.stats.order_counts[order - 1] += 1;
        if self.opts.record_steps {
            self.stats.step_history.push((self.t, h, order));
        }
        let worst =
            (0..self.n).max_by(|&a, &b| (err[a] * w[a]).abs().total_cmp(&(err[b] * w[b]).abs()));
        if let Some(i) = worst {
            self.limiter_counts[i] += 1;
        }
    }

    /// The three unknowns with the largest weighted entries of `v`, for messages.
    pub(crate) fn worst_components(&self, v: &[f64], w: &[f64]) -> String {
        let mut idx: Vec<usize> = (0..self.n).collect();
        idx.sort_by(|&a, &b| (v[b] * w[b]).abs().total_cmp(&(v[a] * w[a]).abs()));
        idx.iter()
            .take(WORST_SHOWN)
            .map(|&i| {
                format!(
                    "{} (weighted {:.2e})",
                    self.prob.var_name(i),
                    (v[i] * w[i]).abs()
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The equations whose residual is not finite, or `None`.
    pub(crate) fn non_finite(&self, res: &[f64]) -> Option<String> {
        if res.iter().all(|v| v.is_finite()) {
            return None;
        }
        let bad: Vec<String> = (0..self.n)
            .filter(|&i| !res[i].is_finite())
            .take(NAMES_SHOWN)
            .map(|i| self.prob.eq_name(i))
            .collect();
        Some(bad.join(", "))
    }

    /// A singular factorisation with the unknowns and equations it names.
    pub(crate) fn describe_singular(&self, s: &Singular) -> String {
        let list = |idx: &[usize], name: &dyn Fn(usize) -> String| {
            idx.iter()
                .take(NAMES_SHOWN)
                .map(|&i| name(i))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut parts = vec![s.detail.clone()];
        if !s.columns.is_empty() {
            parts.push(format!(
                "unknowns: {}",
                list(&s.columns, &|c| self.prob.var_name(c))
            ));
        }
        if !s.rows.is_empty() {
            parts.push(format!(
                "equations: {}",
                list(&s.rows, &|r| self.prob.eq_name(r))
            ));
        }
        parts.join("; ")
    }
}

/// Weights of the norms: 1/(atol + rtol |y|) of the step's start, and from them those of
/// the error and Newton norms and the Newton matrix's column scaling, which each method
/// sets for its step.
pub(crate) struct Weights {
    pub ewt: Vec<f64>,
    pub err: Vec<f64>,
    pub newton: Vec<f64>,
    pub col_scale: Vec<f64>,
}

impl Weights {
    pub fn new(n: usize) -> Self {
        Self {
            ewt: vec![0.0; n],
            err: vec![0.0; n],
            newton: vec![0.0; n],
            col_scale: vec![1.0; n],
        }
    }

    /// ewt_i = 1/(rtol |y_i| + atol(i)); a vector-valued unknown (`groups`) takes the
    /// vector's length for |y_i|.
    pub fn set_ewt(
        &mut self,
        y: &[f64],
        rtol: f64,
        atol: impl Fn(usize) -> f64,
        groups: &[Range<usize>],
    ) {
        for i in 0..y.len() {
            self.ewt[i] = 1.0 / (rtol * y[i].abs() + atol(i));
        }
        for g in groups {
            let len = y[g.clone()].iter().map(|y| y * y).sum::<f64>().sqrt();
            for i in g.clone() {
                self.ewt[i] = 1.0 / (rtol * len + atol(i));
            }
        }
    }
}

/// Weighted RMS norm.
pub(crate) fn wrms(v: &[f64], w: &[f64]) -> f64 {
    let s: f64 = v.iter().zip(w).map(|(a, b)| (a * b) * (a * b)).sum();
    (s / v.len() as f64).sqrt()
}

/// An integration method bound to one problem. The methods implement where they differ
/// (their start, their step and their interpolant); the driver to an output time, the
/// stop time, events and the statistics are written once here on top of them.
///
/// Object safe: [`crate::Integrator`] holds the method `SolverOptions::method` names as
/// a `dyn DaeMethod`.
pub trait DaeMethod<'a, P: DaeProblem + ?Sized + 'a> {
    /// The state the driver shares with the method.
    fn core(&self) -> &Core<'a, P>;

    /// The same, mutable.
    fn core_mut(&mut self) -> &mut Core<'a, P>;

    /// Sets the first step from the first output time `tout` (`tout` != `t()`); called
    /// once, by the first [`advance`](Self::advance).
    fn start(&mut self, tout: f64) -> Result<(), SolverError>;

    /// One accepted step from `t()`, with the method's retries after failures. Needs
    /// [`start`](Self::start) first.
    fn step(&mut self) -> Result<(), SolverError>;

    /// y and y' at `t` from the interpolant of the last step (valid for t in
    /// [t() - h_used, t()]).
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]);

    /// The step size in the event-time tolerance 100 uround (|t| + |h|) (the BDF: the
    /// next step, as IDA's hh; Radau IIA: the last); `None` while there is no step to
    /// search.
    fn root_step(&self) -> Option<f64>;

    /// Current internal time (the end of the last accepted step).
    fn t(&self) -> f64 {
        self.core().t
    }

    /// Counters of the integration so far.
    fn stats<'s>(&'s self) -> &'s Stats
    where
        'a: 's,
    {
        &self.core().stats
    }

    /// The settings the integrator runs with.
    fn options<'s>(&'s self) -> &'s SolverOptions
    where
        'a: 's,
    {
        &self.core().opts
    }

    /// Never step past `tstop` (for example the end of the road or of the run).
    fn set_stop_time(&mut self, tstop: f64) {
        self.core_mut().tstop = Some(tstop);
    }

    /// The `k` unknowns that dominated the error estimate in the most accepted steps, by
    /// name, with their step counts: what sets the step size.
    fn step_limiters(&self, k: usize) -> Vec<(String, usize)> {
        let c = self.core();
        let mut idx: Vec<usize> = (0..c.n).filter(|&i| c.limiter_counts[i] > 0).collect();
        idx.sort_by_key(|&i| std::cmp::Reverse(c.limiter_counts[i]));
        idx.iter()
            .take(k)
            .map(|&i| (c.prob.var_name(i), c.limiter_counts[i]))
            .collect()
    }

    /// Integrates until the internal time reaches `tout` (or the stop time) or an event
    /// function changes sign.
    fn advance(&mut self, tout: f64) -> Result<Advance, SolverError> {
        let (t, h_used) = (self.core().t, self.core().h_used);
        if !tout.is_finite() {
            return Err(SolverError::BadOutputTime { tout, t });
        }
        if !self.core().started {
            if (tout - t).abs() == 0.0 {
                return Err(SolverError::BadOutputTime { tout, t });
            }
            self.start(tout)?;
            self.core_mut().started = true;
        } else if tout < t - h_used {
            return Err(SolverError::BadOutputTime { tout, t });
        }
        // A root between the last reported root and t may still be pending.
        if let Some(r) = self.check_roots() {
            return Ok(r);
        }
        let max_steps = self.core().opts.max_steps;
        let mut steps_here = 0usize;
        while self.core().t < tout {
            let c = self.core_mut();
            if let Some(ts) = c.tstop {
                if c.t >= ts - TSTOP_UROUNDS * f64::EPSILON * ts.abs().max(1.0) {
                    c.t = ts;
                    return Ok(Advance::Reached);
                }
            }
            if steps_here >= max_steps {
                return Err(SolverError::TooManySteps { t: c.t, max_steps });
            }
            self.step()?;
            steps_here += 1;
            if let Some(r) = self.check_roots() {
                return Ok(r);
            }
        }
        Ok(Advance::Reached)
    }

    /// Events over the last step, located on its interpolant.
    fn check_roots(&mut self) -> Option<Advance> {
        let c = self.core();
        if c.roots.is_empty() || !c.started {
            return None;
        }
        let h = self.root_step()?;
        let mut roots = std::mem::take(&mut self.core_mut().roots);
        let mut evals = self.core().stats.root_evals;
        let found = roots.check(
            self.core().prob,
            self.core().t,
            h,
            &|t, y, yp| self.interpolate(t, y, yp),
            &mut evals,
        );
        let c = self.core_mut();
        c.stats.root_evals = evals;
        c.roots = roots;
        found
    }
}
