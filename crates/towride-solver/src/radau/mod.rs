//! The 3-stage Radau IIA method (order 5, L-stable, stiffly accurate) for
//! F(t, y, y') = 0, following Hairer and Wanner's RADAU5 (Solving ODEs II, sections IV.8
//! and VI.1-VI.4 for the differential-algebraic case; Fortran RADAU5 of July 9, 1996,
//! subroutines RADCOR, ESTRAD, SLVRAD, CONTR5).
//!
//! A step from (t0, y0) with size h solves for the stage increments Z_i = Y_i - y0,
//! i = 1..3, the collocation equations
//!
//! ```text
//! F(t0 + c_i h, y0 + Z_i, Y'_i) = 0,   h Y'_i = sum_j (A^-1)_ij Z_j,
//! ```
//!
//! by simplified Newton on the transformed increments W = (T^-1 (x) I) Z, with which the
//! block iteration matrix I (x) J_y + (1/h) A^-1 (x) J_y' splits into one real matrix
//! J_y + (gamma/h) J_y' and one complex matrix J_y + ((alpha + i beta)/h) J_y'
//! ([`newton`]). The new solution is y0 + Z_3 (stiffly accurate), its derivative Y'_3.
//! The error estimate of the embedded third-order formula is filtered by
//! (J_y + (gamma/h) J_y')^-1 ([`control`]); the step follows Gustafsson's predictive
//! controller; the collocation polynomial gives dense output ([`dense`]).
//!
//! RADAU5 integrates M y' = f(t, y). For F(t, y, y') = M y' - f(t, y) every formula here
//! reduces to RADAU5's; where RADAU5 evaluates f at a point, this code evaluates -F with
//! the derivative that makes the two agree for any F linear in y' (`control.rs`).

use crate::error::SolverError;
use crate::jacobian::JacobianEval;
use crate::linear::{ComplexMatrix, NewtonMatrix};
use crate::options::{AlgebraicControl, JacobianSource, LinearSolver, SolverOptions, Stats};
use crate::problem::{DaeProblem, VarKind};
use crate::roots::Roots;
use crate::Advance;

mod control;
mod dense;
mod newton;
pub mod tableau;

const UROUND: f64 = f64::EPSILON;
/// Largest fraction of tstop's magnitude, in rounding units, by which the end of a step
/// may miss tstop and still count as reaching it.
const TSTOP_UROUNDS: f64 = 4.0;
/// A step that would end within this factor of its size before tstop is stretched to
/// end there (RADAU5: X + 1.0001 H >= XEND).
const STRETCH_TO_STOP: f64 = 1.0001;
/// RADAU5 gives up when 0.1 |h| <= |t| uround.
const STEP_TOO_SMALL: f64 = 0.1;
/// Singular factorisations in a row after which the run ends (RADAU5: NSING >= 5).
const MAX_SINGULAR: usize = 5;
/// The first step when the options give none: this fraction of the distance to the
/// first output time, limited by 0.5 / ||y'0|| (IDA's rule, as for the BDF).
const H0_FRACTION: f64 = 0.001;
const H0_NORM: f64 = 0.5;

/// The Radau IIA integrator bound to one problem.
pub struct Radau5<'a, P: DaeProblem + ?Sized> {
    prob: &'a P,
    opts: SolverOptions,
    n: usize,
    kinds: Vec<VarKind>,
    /// Error control of the algebraic unknowns with `Auto` resolved.
    algebraic: AlgebraicControl,
    /// Vector-valued unknowns weighted by their length (`vector_error_weights`).
    groups: Vec<std::ops::Range<usize>>,
    /// A^-1 of the method.
    ainv: [[f64; 3]; 3],
    /// Tolerances as RADAU5 uses them inside (`control::internal_tolerances`).
    rtol: f64,
    atol: Vec<f64>,
    /// Newton stopping constant (RADAU5's FNEWT).
    fnewt: f64,
    // State at the end of the last accepted step.
    t: f64,
    y: Vec<f64>,
    yp: Vec<f64>,
    /// The step to attempt next and the last accepted one.
    h: f64,
    h_old: f64,
    /// Dense output of the last accepted step (RADAU5's CONT, with cont[0] = y).
    cont: [Vec<f64>; 4],
    // Stage work vectors: increments Z, transformed increments W, Newton corrections.
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    dw: [Vec<f64>; 3],
    ys: Vec<f64>,
    yps: Vec<f64>,
    res: Vec<f64>,
    /// Error weights 1/(atol + rtol |y|) of the step's start, and the weights of the
    /// error and Newton norms (index-k unknowns times h^(k-1)).
    ewt: Vec<f64>,
    wt_err: Vec<f64>,
    wt_newton: Vec<f64>,
    col_scale: Vec<f64>,
    /// The error estimate of the last attempt (for the step limiters).
    err_vec: Vec<f64>,
    // Iteration matrices.
    jac: NewtonMatrix,
    cjac: ComplexMatrix,
    jeval: JacobianEval,
    /// A Jacobian is kept (dF/dy and dF/dy').
    jac_valid: bool,
    /// It was evaluated for the step being attempted (RADAU5's CALJAC).
    jac_fresh: bool,
    /// Why the next evaluation happens (for `Stats::matrix_rebuilds`): the first step or a
    /// failed error test (`invalid`), else slow or failed Newton (`convergence`).
    slow_newton: bool,
    /// The step the factorisations were made for (0: none).
    h_factored: f64,
    /// The state the Jacobian was evaluated at (for the frame transport).
    y_built: Vec<f64>,
    /// The middle stage's state, to which a Newton solve carries the matrix.
    y_mid: Vec<f64>,
    transport: bool,
    // Step control.
    /// RADAU5's FACCON: theta/(1 - theta) of the last Newton iteration, carried over.
    faccon: f64,
    /// Contraction rate of the last Newton iteration (RADAU5's THETA).
    theta: f64,
    first: bool,
    reject: bool,
    /// Step and error of the last accepted step (Gustafsson's controller).
    h_acc: f64,
    err_acc: f64,
    singular_in_row: usize,
    started: bool,
    tstop: Option<f64>,
    roots: Roots,
    stats: Stats,
    /// Accepted steps in which each unknown dominated the error estimate.
    limiter_counts: Vec<usize>,
}

impl<'a, P: DaeProblem + ?Sized> Radau5<'a, P> {
    /// Sets up the integrator at (t0, y0, y'0); the initial values must be consistent.
    pub fn new(
        prob: &'a P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: SolverOptions,
    ) -> Result<Self, SolverError> {
        let n = prob.size();
        opts.validate(n)?;
        let kinds = crate::problem::check_start(prob, t0, y0, yp0)?;
        let algebraic = control::resolve_algebraic(opts.algebraic, &kinds);
        let pattern = prob.jacobian_pattern();
        let dense = match opts.linear_solver {
            LinearSolver::Dense => true,
            LinearSolver::Sparse => false,
            LinearSolver::Auto => pattern.is_none() || n < opts.dense_limit,
        };
        let jac = NewtonMatrix::new(n, pattern, dense)?;
        let cjac = ComplexMatrix::like(&jac)?;
        let (rtol, atol) = control::internal_tolerances(&opts, n);
        let fnewt = control::newton_stop(rtol, &atol);
        let zero = || vec![0.0; n];
        let mut stats = Stats::default();
        let roots = Roots::new(prob, t0, y0, yp0, &mut stats.root_evals);
        let mut s = Self {
            prob,
            n,
            kinds,
            algebraic,
            groups: if opts.vector_error_weights {
                prob.magnitude_groups()
            } else {
                Vec::new()
            },
            ainv: tableau::a_inverse(),
            rtol,
            atol,
            fnewt,
            t: t0,
            y: y0.to_vec(),
            yp: yp0.to_vec(),
            h: 0.0,
            h_old: 0.0,
            cont: [y0.to_vec(), zero(), zero(), zero()],
            z: [zero(), zero(), zero()],
            w: [zero(), zero(), zero()],
            dw: [zero(), zero(), zero()],
            ys: zero(),
            yps: zero(),
            res: zero(),
            ewt: zero(),
            wt_err: zero(),
            wt_newton: zero(),
            col_scale: vec![1.0; n],
            err_vec: zero(),
            jac,
            cjac,
            jeval: JacobianEval::new(opts.jacobian == JacobianSource::Auto),
            jac_valid: false,
            jac_fresh: false,
            slow_newton: false,
            h_factored: 0.0,
            y_built: zero(),
            y_mid: zero(),
            transport: opts.matrix_transport && prob.has_transport(),
            faccon: 1.0,
            theta: 0.0,
            first: true,
            reject: false,
            h_acc: 0.0,
            err_acc: 0.0,
            singular_in_row: 0,
            started: false,
            tstop: None,
            roots,
            stats,
            limiter_counts: vec![0; n],
            opts,
        };
        s.set_ewt();
        Ok(s)
    }

    /// Never step past `tstop`.
    pub fn set_stop_time(&mut self, tstop: f64) {
        self.tstop = Some(tstop);
    }

    /// Current internal time (the end of the last accepted step).
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Counters of the integration so far.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The settings the integrator runs with.
    pub fn options(&self) -> &SolverOptions {
        &self.opts
    }

    /// The `k` unknowns that dominated the error estimate in the most accepted steps.
    pub fn step_limiters(&self, k: usize) -> Vec<(String, usize)> {
        let mut idx: Vec<usize> = (0..self.n)
            .filter(|&i| self.limiter_counts[i] > 0)
            .collect();
        idx.sort_by_key(|&i| std::cmp::Reverse(self.limiter_counts[i]));
        idx.iter()
            .take(k)
            .map(|&i| (self.prob.var_name(i), self.limiter_counts[i]))
            .collect()
    }

    /// Integrates until the internal time reaches `tout` or an event function changes sign.
    pub fn advance(&mut self, tout: f64) -> Result<Advance, SolverError> {
        if !tout.is_finite() {
            return Err(SolverError::BadOutputTime { tout, t: self.t });
        }
        if !self.started {
            self.start(tout)?;
        } else if tout < self.t - self.h_old {
            return Err(SolverError::BadOutputTime { tout, t: self.t });
        }
        if let Some(r) = self.check_roots() {
            return Ok(r);
        }
        crate::integrator::drive(self, tout)
    }

    /// The first step: the options' `h_init`, or IDA's rule as the BDF uses it.
    fn start(&mut self, tout: f64) -> Result<(), SolverError> {
        let tdist = (tout - self.t).abs();
        if tdist == 0.0 {
            return Err(SolverError::BadOutputTime { tout, t: self.t });
        }
        let h = match self.opts.h_init {
            Some(h) => h,
            None => {
                let h = H0_FRACTION * tdist;
                let mut sum = 0.0;
                for i in 0..self.n {
                    if self.kinds[i] == VarKind::Differential {
                        sum += (self.yp[i] * self.ewt[i]).powi(2);
                    }
                }
                let ypnorm = (sum / self.n as f64).sqrt();
                if ypnorm > H0_NORM / h {
                    H0_NORM / ypnorm
                } else {
                    h
                }
            }
        };
        self.h = h.min(self.opts.h_max);
        self.started = true;
        Ok(())
    }

    /// Limits the step to attempt by the problem's and the options' maximum and by tstop.
    fn limit_step(&mut self) {
        if let Some(hl) = self.prob.max_step(self.t, &self.y) {
            self.h = self.h.min(hl);
        }
        self.h = self.h.min(self.opts.h_max);
        if let Some(ts) = self.tstop {
            if self.t + STRETCH_TO_STOP * self.h >= ts {
                self.h = ts - self.t;
            }
        }
    }

    /// One accepted step, with the retries RADAU5 makes (RADCOR, labels 10 to 78).
    fn step(&mut self) -> Result<(), SolverError> {
        self.limit_step();
        let mut conv_failures = 0usize;
        let mut err_failures = 0usize;
        loop {
            if self.h.abs() < self.opts.h_min
                || STEP_TOO_SMALL * self.h.abs() <= self.t.abs() * UROUND
                || self.h <= 0.0
            {
                return Err(SolverError::StepTooSmall {
                    t: self.t,
                    h: self.h,
                    h_min: self.opts.h_min,
                });
            }
            self.set_step_weights();
            let outcome = self.prepare_matrices().and_then(|()| {
                self.starting_values();
                self.newton()
            });
            let newt = match outcome {
                Ok(newt) => newt,
                Err(fail) => {
                    conv_failures += 1;
                    self.stats.convergence_failures += 1;
                    self.stats.rejected_steps += 1;
                    let factor = self.newton_failed(&fail, conv_failures)?;
                    self.h *= factor;
                    self.reject = true;
                    continue;
                }
            };
            let err = self.error_estimate()?;
            let mut hnew = self.h / control::step_quotient(err, newt, &self.opts.radau);
            if err < 1.0 {
                self.singular_in_row = 0;
                hnew = self.accept(err, hnew);
                self.next_step(hnew);
                return Ok(());
            }
            err_failures += 1;
            self.stats.error_test_failures += 1;
            self.stats.rejected_steps += 1;
            if err_failures >= self.opts.max_error_failures {
                return Err(SolverError::ErrorTestFailure {
                    t: self.t,
                    h: self.h,
                    failures: err_failures,
                    worst: self.worst_components(&self.err_vec, &self.wt_err),
                });
            }
            self.reject = true;
            self.h = if self.first {
                FIRST_STEP_CUT * self.h
            } else {
                hnew
            };
            if !self.jac_fresh {
                self.jac_valid = false;
                self.slow_newton = false;
            }
        }
    }

    /// The state of the accepted step becomes current; returns the next step proposed
    /// by Gustafsson's controller.
    fn accept(&mut self, err: f64, hnew: f64) -> f64 {
        let hnew = control::gustafsson(self, err, hnew);
        self.first = false;
        self.stats.steps += 1;
        self.stats.last_order = 5;
        self.stats.last_step = self.h;
        self.stats.order_counts[4] += 1;
        self.count_limiter();
        let t0 = self.t;
        self.t = t0 + self.h;
        if let Some(ts) = self.tstop {
            if (self.t - ts).abs() <= TSTOP_UROUNDS * UROUND * ts.abs().max(1.0) {
                self.t = ts;
            }
        }
        self.h_old = self.h;
        self.stage_derivative(2);
        std::mem::swap(&mut self.yp, &mut self.yps);
        for i in 0..self.n {
            self.y[i] += self.z[2][i];
        }
        dense::update(&mut self.cont, &self.y, &self.z);
        if self.opts.record_steps {
            self.stats.step_history.push((self.t, self.h, 5));
        }
        self.set_ewt();
        self.jac_fresh = false;
        hnew
    }

    /// The step after an accepted one, and whether the Jacobian is kept (RADCOR after
    /// label 30: a Newton iteration that contracted fast keeps it; a step ratio within
    /// [1, keep_step_ratio] keeps the step and the factorisations).
    fn next_step(&mut self, hnew: f64) {
        let mut hnew = hnew.min(self.opts.h_max);
        if self.reject {
            hnew = hnew.min(self.h);
        }
        self.reject = false;
        let keep_jacobian = self.theta <= self.opts.radau.jacobian_theta;
        let q = hnew / self.h;
        if !(keep_jacobian && (1.0..=self.opts.radau.keep_step_ratio).contains(&q)) {
            self.h = hnew;
        }
        if !keep_jacobian {
            self.jac_valid = false;
            self.slow_newton = true;
        }
    }

    /// y and y' at `t` from the collocation polynomial of the last step (RADAU5's
    /// CONTR5 and its derivative); accurate for t in [t - h_old, t].
    pub fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        if self.stats.steps == 0 {
            y.copy_from_slice(&self.y);
            yp.copy_from_slice(&self.yp);
            return;
        }
        dense::eval(&self.cont, self.t, self.h_old, t, y, yp);
    }

    /// Events over the last step, located on its collocation polynomial.
    fn check_roots(&mut self) -> Option<Advance> {
        if self.roots.is_empty() || !self.started || self.stats.steps == 0 {
            return None;
        }
        let mut roots = std::mem::take(&mut self.roots);
        let mut evals = self.stats.root_evals;
        let found = roots.check(
            self.prob,
            self.t,
            self.h_old,
            &|t, y, yp| self.interpolate(t, y, yp),
            &mut evals,
        );
        self.stats.root_evals = evals;
        self.roots = roots;
        found
    }

    fn count_limiter(&mut self) {
        let worst = (0..self.n).max_by(|&a, &b| {
            (self.err_vec[a] * self.wt_err[a])
                .abs()
                .total_cmp(&(self.err_vec[b] * self.wt_err[b]).abs())
        });
        if let Some(i) = worst {
            self.limiter_counts[i] += 1;
        }
    }

    fn worst_components(&self, v: &[f64], w: &[f64]) -> String {
        let mut idx: Vec<usize> = (0..self.n).collect();
        idx.sort_by(|&a, &b| (v[b] * w[b]).abs().total_cmp(&(v[a] * w[a]).abs()));
        idx.iter()
            .take(3)
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
}

/// After a rejected first step the step is cut tenfold (RADAU5: H = H*0.1 when FIRST).
const FIRST_STEP_CUT: f64 = 0.1;

impl<P: DaeProblem + ?Sized> crate::integrator::Stepping for Radau5<'_, P> {
    fn now(&self) -> f64 {
        self.t
    }
    fn finish_at(&mut self, t: f64) {
        self.t = t;
    }
    fn stop_time(&self) -> Option<f64> {
        self.tstop
    }
    fn max_steps(&self) -> usize {
        self.opts.max_steps
    }
    fn step(&mut self) -> Result<(), SolverError> {
        Radau5::step(self)
    }
    fn check_roots(&mut self) -> Option<Advance> {
        Radau5::check_roots(self)
    }
}
