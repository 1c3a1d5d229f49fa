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
use crate::method::{Core, DaeMethod, Weights};
use crate::options::{JacobianSource, SolverOptions};
use crate::problem::DaeProblem;

mod control;
mod dense;
mod newton;
pub mod tableau;

const UROUND: f64 = f64::EPSILON;
/// A step that would end within this factor of its size before tstop is stretched to
/// end there (RADAU5: X + 1.0001 H >= XEND).
const STRETCH_TO_STOP: f64 = 1.0001;
/// RADAU5 gives up when 0.1 |h| <= |t| uround.
const STEP_TOO_SMALL: f64 = 0.1;
/// Singular factorisations in a row after which the run ends (RADAU5: NSING >= 5).
const MAX_SINGULAR: usize = 5;
/// After a rejected first step the step is cut tenfold (RADAU5: H = H*0.1 when FIRST).
const FIRST_STEP_CUT: f64 = 0.1;

/// The order Radau IIA's steps are booked at (its classical order).
const ORDER: usize = 5;

/// The iteration matrices and what they were made for.
struct Matrices {
    /// The real matrix J_y + (gamma/h) J_y', kept with its parts J_y and J_y'.
    jac: NewtonMatrix,
    /// The complex matrix J_y + ((alpha + i beta)/h) J_y'.
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
}

/// Stage work vectors: increments Z, transformed increments W, Newton corrections, a
/// stage's state, derivative and residual, and the error estimate.
struct Stages {
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    dw: [Vec<f64>; 3],
    ys: Vec<f64>,
    yps: Vec<f64>,
    res: Vec<f64>,
    /// The error estimate of the last attempt (for the step limiters).
    err_vec: Vec<f64>,
}

/// Newton and step-size control carried from step to step.
struct Control {
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
}

/// The Radau IIA integrator bound to one problem.
pub struct Radau5<'a, P: DaeProblem + ?Sized> {
    core: Core<'a, P>,
    wt: Weights,
    /// A^-1 of the method.
    ainv: [[f64; 3]; 3],
    /// Tolerances as RADAU5 uses them inside (`control::internal_tolerances`).
    rtol: f64,
    atol: Vec<f64>,
    /// Newton stopping constant (RADAU5's FNEWT).
    fnewt: f64,
    // State at the end of the last accepted step (its time is `core.t`).
    y: Vec<f64>,
    yp: Vec<f64>,
    /// The step to attempt next (the last accepted one is `core.h_used`).
    h: f64,
    /// Dense output of the last accepted step (RADAU5's CONT, with cont[0] = y).
    cont: [Vec<f64>; 4],
    st: Stages,
    mats: Matrices,
    ctl: Control,
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
        let mut core = Core::new(prob, t0, y0, yp0, opts)?;
        let opts = &core.opts;
        if opts.vector_error_weights {
            core.groups = prob.magnitude_groups();
        }
        let jac = core.newton_matrix()?;
        let cjac = ComplexMatrix::like(&jac)?;
        let (rtol, atol) = control::internal_tolerances(opts, n);
        let fnewt = control::newton_stop(rtol, &atol);
        let zero = || vec![0.0; n];
        let mats = Matrices {
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
        };
        let mut s = Self {
            core,
            wt: Weights::new(n),
            ainv: tableau::a_inverse(),
            rtol,
            atol,
            fnewt,
            y: y0.to_vec(),
            yp: yp0.to_vec(),
            h: 0.0,
            cont: [y0.to_vec(), zero(), zero(), zero()],
            st: Stages {
                z: [zero(), zero(), zero()],
                w: [zero(), zero(), zero()],
                dw: [zero(), zero(), zero()],
                ys: zero(),
                yps: zero(),
                res: zero(),
                err_vec: zero(),
            },
            mats,
            ctl: Control {
                faccon: 1.0,
                theta: 0.0,
                first: true,
                reject: false,
                h_acc: 0.0,
                err_acc: 0.0,
                singular_in_row: 0,
            },
        };
        s.set_ewt();
        Ok(s)
    }

    /// Limits the step to attempt by the problem's and the options' maximum and by tstop.
    fn limit_step(&mut self) {
        let c = &self.core;
        if let Some(hl) = c.prob.max_step(c.t, &self.y) {
            self.h = self.h.min(hl);
        }
        self.h = self.h.min(c.opts.h_max);
        if let Some(ts) = c.tstop {
            if c.t + STRETCH_TO_STOP * self.h >= ts {
                self.h = ts - c.t;
            }
        }
    }

    /// One accepted step, with the retries RADAU5 makes (RADCOR, labels 10 to 78).
    fn radcor_step(&mut self) -> Result<(), SolverError> {
        self.limit_step();
        let mut conv_failures = 0usize;
        loop {
            let t = self.core.t;
            if self.h.abs() < self.core.opts.h_min
                || STEP_TOO_SMALL * self.h.abs() <= t.abs() * UROUND
                || self.h <= 0.0
            {
                return Err(SolverError::StepTooSmall {
                    t,
                    h: self.h,
                    h_min: self.core.opts.h_min,
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
                    self.core.stats.convergence_failures += 1;
                    self.core.stats.rejected_steps += 1;
                    let factor = self.newton_failed(&fail, conv_failures)?;
                    self.h *= factor;
                    self.ctl.reject = true;
                    continue;
                }
            };
            let err = self.error_estimate()?;
            let mut hnew = self.h / control::step_quotient(err, newt, &self.core.opts.radau);
            if err < 1.0 {
                self.ctl.singular_in_row = 0;
                hnew = self.accept(err, hnew);
                self.next_step(hnew);
                return Ok(());
            }
            // No limit on the failures as in RADAU5 (RADCOR, "STEP IS REJECTED"): each
            // cuts the step by at least 1 / SAFE, and the step-size guard above ends a
            // step that cannot pass. A stiff component forced across a kink (a tyre's
            // effective road meeting an obstacle's foot) keeps its estimate near 1 until
            // h is below its time constant: IDA's ten failures ended such runs at h = 1e-6 s.
            self.core.stats.error_test_failures += 1;
            self.core.stats.rejected_steps += 1;
            self.ctl.reject = true;
            self.h = if self.ctl.first {
                FIRST_STEP_CUT * self.h
            } else {
                hnew
            };
            if !self.mats.jac_fresh {
                self.mats.jac_valid = false;
                self.mats.slow_newton = false;
            }
        }
    }

    /// The state of the accepted step becomes current; returns the next step proposed
    /// by Gustafsson's controller.
    fn accept(&mut self, err: f64, hnew: f64) -> f64 {
        let hnew = control::gustafsson(self, err, hnew);
        self.ctl.first = false;
        self.core.t = self.core.snap_to_stop(self.core.t + self.h);
        self.core
            .book_step(self.h, ORDER, &self.st.err_vec, &self.wt.err);
        self.stage_derivative(2);
        std::mem::swap(&mut self.yp, &mut self.st.yps);
        for i in 0..self.core.n {
            self.y[i] += self.st.z[2][i];
        }
        dense::update(&mut self.cont, &self.y, &self.st.z);
        self.set_ewt();
        self.mats.jac_fresh = false;
        hnew
    }

    /// The step after an accepted one, and whether the Jacobian is kept (RADCOR after
    /// label 30: a Newton iteration that contracted fast keeps it; a step ratio within
    /// [1, keep_step_ratio] keeps the step and the factorisations).
    fn next_step(&mut self, hnew: f64) {
        let radau = &self.core.opts.radau;
        let mut hnew = hnew.min(self.core.opts.h_max);
        if self.ctl.reject {
            hnew = hnew.min(self.h);
        }
        self.ctl.reject = false;
        let keep_jacobian = self.ctl.theta <= radau.jacobian_theta;
        let q = hnew / self.h;
        if !(keep_jacobian && (1.0..=radau.keep_step_ratio).contains(&q)) {
            self.h = hnew;
        }
        if !keep_jacobian {
            self.mats.jac_valid = false;
            self.mats.slow_newton = true;
        }
    }
}

impl<'a, P: DaeProblem + ?Sized> DaeMethod<'a, P> for Radau5<'a, P> {
    fn core(&self) -> &Core<'a, P> {
        &self.core
    }

    fn core_mut(&mut self) -> &mut Core<'a, P> {
        &mut self.core
    }

    /// The first step: the options' `h_init`, or IDA's rule as the BDF uses it.
    fn start(&mut self, tout: f64) -> Result<(), SolverError> {
        self.h = self.core.initial_step(tout, &self.yp, &self.wt.ewt);
        Ok(())
    }

    fn step(&mut self) -> Result<(), SolverError> {
        debug_assert!(self.core.started, "`advance` starts the integration");
        self.radcor_step()
    }

    /// y and y' at `t` from the collocation polynomial of the last step (RADAU5's
    /// CONTR5 and its derivative); accurate for t in [t - h_used, t].
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        if self.core.stats.steps == 0 {
            y.copy_from_slice(&self.y);
            yp.copy_from_slice(&self.yp);
            return;
        }
        dense::eval(&self.cont, self.core.t, self.core.h_used, t, y, yp);
    }

    /// Events are searched on the collocation polynomial of the last step, which needs
    /// one.
    fn root_step(&self) -> Option<f64> {
        (self.core.stats.steps > 0).then_some(self.core.h_used)
    }
}
