//! Variable-order, variable-step BDF for F(t, y, y') = 0 in fixed-leading-coefficient
//! form, following SUNDIALS IDA (Hindmarsh et al., "SUNDIALS: Suite of nonlinear and
//! differential/algebraic equation solvers", ACM TOMS 31 (2005); IDA's `ida.c`, the
//! functions IDASetCoeffs, IDAPredict, IDATestError, IDAHandleNFlag, IDACompleteStep,
//! IDAGetSolution) and DASSL (Brenan, Campbell & Petzold 1996, ch. 5).
//!
//! The history is kept as modified divided differences phi[j]; the fixed-coefficient
//! variant keeps backward differences on an equally spaced grid and interpolates them
//! onto the new grid when the step changes (Shampine & Reichelt 1997, ode15s).

use super::error::SolverError;
use super::jacobian::JacobianEval;
use super::linear::{NewtonMatrix, Singular};
use super::method::{Core, DaeMethod, Weights};
use super::options::{AlgebraicControl, JacobianSource, Method, SolverOptions};
use super::problem::DaeProblem;

mod control;
mod history;
mod newton;
mod stald;

use history::rescale_differences;
use stald::Stald;

pub(crate) const MAXORD: usize = 5;
const UROUND: f64 = f64::EPSILON;

// Step-size factors of IDA (`ida.c`, IDAHandleNFlag and IDACompleteStep; the values of
// `ida_impl.h`'s ETA_*_DEFAULT, which IDASetEta* may change).
/// The step grows only when the estimate allows at least this factor (ETA_MAX_FX), the
/// default of `SolverOptions::eta_fixed_max`.
pub(crate) const ETA_MAX_FX: f64 = 2.0;
/// Largest step growth (ETA_MAX), also the doubling of the start-up phase.
const ETA_MAX: f64 = 2.0;
/// A step is cut once the estimated factor is at most this (ETA_MIN_FX) ...
const ETA_MIN_FX: f64 = 1.0;
/// ... to a factor within [ETA_MIN, ETA_LOW].
const ETA_MIN: f64 = 0.5;
const ETA_LOW: f64 = 0.9;
/// Smallest factor after a first error-test failure, the factor after later ones
/// (ETA_MIN_EF).
const ETA_MIN_EF: f64 = 0.25;
/// The factor after a Newton failure (ETA_CF).
const ETA_CF: f64 = 0.25;
/// Safety factor of the step after a first error-test failure (IDA's PT9 in
/// IDAHandleNFlag).
const ETA_EF_SAFETY: f64 = 0.9;
/// Added to 2 err_k in the factor (2 err_k + PT0001)^(-1/(k+1)) so that a vanishing
/// error estimate gives a bounded factor (IDA's PT0001).
const ERR_BIAS: f64 = 0.0001;
/// Newton convergence-test constant (EPCON), the default of `SolverOptions::newton_tol`.
pub(crate) const EPCON: f64 = 0.33;
/// A step below this many rounding units of max(|t|, 1) ends the run.
const HMIN_UROUNDS: f64 = 10.0;

/// Why an attempt failed in the corrector.
enum StepFail {
    Convergence(String),
    Singular(Singular),
    NonFinite(String),
}

/// The history (IDA's modified divided differences) and the coefficients of the step
/// being attempted (IDASetCoeffs; IDA names).
struct History {
    phi: Vec<Vec<f64>>,
    psi: [f64; MAXORD + 2],
    alpha: [f64; MAXORD + 2],
    beta: [f64; MAXORD + 2],
    sigma: [f64; MAXORD + 2],
    gamma: [f64; MAXORD + 2],
    /// Leading coefficient of the step, and of the last step.
    cj: f64,
    cjlast: f64,
    /// Error constant of the step.
    ck: f64,
    /// phi and psi before the attempt, restored after a failure.
    backup_phi: Vec<Vec<f64>>,
    backup_psi: [f64; MAXORD + 2],
}

/// Step size and order (IDA names).
struct StepControl {
    /// The step to attempt.
    hh: f64,
    /// Order to attempt, order of the last accepted step, order after a failure.
    kk: usize,
    kused: usize,
    knew: usize,
    /// Steps taken at constant step and order (at most kused + 2).
    ns: usize,
    /// 0 during the start-up phase (order up and step doubled each step).
    phase: u8,
    /// Scaled error estimates at orders k and k - 1 of the last attempt.
    err_k: f64,
    err_km1: f64,
}

/// The corrector's state: the iteration matrix, when and where it was built, and IDA's
/// convergence-rate estimate.
struct Newton {
    jac: NewtonMatrix,
    /// Jacobian evaluation (analytic or finite differences) and its buffers.
    jeval: JacobianEval,
    jac_valid: bool,
    jac_age: usize,
    /// cj at the last factorisation, and cj / cjold.
    cjold: f64,
    cjratio: f64,
    /// Rate factor R / (1 - R) of the convergence test, and the first correction's norm.
    ss: f64,
    oldnrm: f64,
    /// The state the iteration matrix was evaluated at (for the problem's frame
    /// transport, and for dF/dy' when it is recombined).
    y_built: Vec<f64>,
    yp_built: Vec<f64>,
    t_built: f64,
    /// Whether the problem's frame transport is used.
    transport: bool,
}

/// Work vectors of an attempt.
struct Work {
    /// The corrector's iterate and its derivative.
    yy: Vec<f64>,
    yp: Vec<f64>,
    /// The predictor.
    ypred: Vec<f64>,
    yppred: Vec<f64>,
    /// Accumulated correction: the local error estimate once converged.
    ee: Vec<f64>,
    delta: Vec<f64>,
    res: Vec<f64>,
    /// For the error estimates at neighbouring orders.
    scratch: Vec<f64>,
}

/// The BDF integrator bound to one problem.
pub struct Bdf<'a, P: DaeProblem + ?Sized> {
    core: Core<'a, P>,
    wt: Weights,
    hist: History,
    ctl: StepControl,
    nls: Newton,
    work: Work,
    /// Stability limit detection's data (`SolverOptions::stability_limit_detection`).
    stald: Stald,
}

impl<'a, P: DaeProblem + ?Sized> Bdf<'a, P> {
    /// Sets up the integrator at (t0, y0, y'0). The initial values must be consistent
    /// (see [`super::ic`] for computing the index-1 part).
    pub fn new(
        prob: &'a P,
        t0: f64,
        y0: &[f64],
        yp0: &[f64],
        opts: SolverOptions,
    ) -> Result<Self, SolverError> {
        if opts.method == Method::Radau5 {
            opts.validate(prob.size())?;
            return Err(SolverError::InvalidSettings {
                field: "method".into(),
                why: "radau5 is not a BDF variant; integrate through `Integrator`, which \
                      chooses by the method"
                    .into(),
            });
        }
        let n = prob.size();
        let mut core = Core::new(prob, t0, y0, yp0, opts)?;
        let opts = &core.opts;
        // Not with fixed coefficients: their step changes interpolate the history onto an
        // equal grid, and the looser weights let the spinning wheels' history grow an
        // interpolation error that no step cut removes (measured: the default scene then
        // fails at every tolerance).
        if opts.vector_error_weights && opts.method == Method::Variable {
            core.groups = prob.magnitude_groups();
        }
        let jac = core.newton_matrix()?;
        let mut phi = vec![vec![0.0; n]; MAXORD + 2];
        phi[0].copy_from_slice(y0);
        phi[1].copy_from_slice(yp0); // scaled by h once the first step size is known
        let nls = Newton {
            jac,
            jeval: JacobianEval::new(opts.jacobian == JacobianSource::Auto),
            jac_valid: false,
            jac_age: 0,
            cjold: 0.0,
            cjratio: 1.0,
            ss: 20.0,
            oldnrm: 0.0,
            y_built: vec![0.0; n],
            yp_built: vec![0.0; n],
            t_built: t0,
            transport: opts.matrix_transport && prob.has_transport(),
        };
        let mut s = Self {
            core,
            wt: Weights::new(n),
            hist: History {
                phi,
                psi: [0.0; MAXORD + 2],
                alpha: [0.0; MAXORD + 2],
                beta: [0.0; MAXORD + 2],
                sigma: [0.0; MAXORD + 2],
                gamma: [0.0; MAXORD + 2],
                cj: 0.0,
                cjlast: 0.0,
                ck: 1.0,
                backup_phi: vec![vec![0.0; n]; MAXORD + 2],
                backup_psi: [0.0; MAXORD + 2],
            },
            ctl: StepControl {
                hh: 0.0,
                kk: 1,
                kused: 0,
                knew: 1,
                ns: 0,
                phase: 0,
                err_k: 0.0,
                err_km1: 0.0,
            },
            nls,
            work: Work {
                yy: y0.to_vec(),
                yp: yp0.to_vec(),
                ypred: vec![0.0; n],
                yppred: vec![0.0; n],
                ee: vec![0.0; n],
                delta: vec![0.0; n],
                res: vec![0.0; n],
                scratch: vec![0.0; n],
            },
            stald: Stald::new(),
        };
        s.set_ewt();
        Ok(s)
    }

    /// True when the dense (not sparse) LU path is in use.
    pub fn uses_dense_lu(&self) -> bool {
        self.nls.jac.is_dense()
    }

    /// Structural non-zeros of the iteration matrix.
    pub fn jacobian_nnz(&self) -> usize {
        self.nls.jac.nnz()
    }

    /// Restarts the integration at a new consistent state (after a discontinuity).
    pub fn reinit(&mut self, t: f64, y: &[f64], yp: &[f64]) -> Result<(), SolverError> {
        if y.iter().chain(yp).any(|v| !v.is_finite()) {
            return Err(SolverError::NonFiniteInitial {
                name: "reinit state".into(),
                value: f64::NAN,
            });
        }
        self.core.t = t;
        self.hist.phi[0].copy_from_slice(y);
        self.hist.phi[1].copy_from_slice(yp);
        self.core.started = false;
        self.nls.jac_valid = false;
        self.set_ewt();
        let c = &mut self.core;
        c.roots.restart(c.prob, t, y, yp, &mut c.stats.root_evals);
        Ok(())
    }

    fn set_ewt(&mut self) {
        let opts = &self.core.opts;
        self.wt.set_ewt(
            &self.hist.phi[0],
            opts.rtol,
            |i| opts.atol_of(i),
            &self.core.groups,
        );
    }

    /// Error-test and Newton weights for the current step size (index-k unknowns get
    /// h^(k-1), Hairer & Wanner II, VII.3).
    fn set_step_weights(&mut self) {
        let hs = self.ctl.hh.abs().min(1.0);
        let wt = &mut self.wt;
        for i in 0..self.core.n {
            let kind = self.core.kinds[i];
            let scale = hs.powi(kind.level() - 1);
            // Unknowns of index k are solved for as h^(k-1) times their correction, which
            // with row equilibration keeps cond(J) bounded as h -> 0.
            wt.col_scale[i] = if self.core.opts.scale_newton_matrix {
                1.0 / scale
            } else {
                1.0
            };
            match self.core.algebraic {
                AlgebraicControl::Full => {
                    wt.err[i] = wt.ewt[i];
                    wt.newton[i] = wt.ewt[i];
                }
                AlgebraicControl::Scaled => {
                    wt.err[i] = wt.ewt[i] * scale;
                    wt.newton[i] = wt.ewt[i] * scale;
                }
                AlgebraicControl::Exclude => {
                    wt.err[i] = if kind.is_algebraic() { 0.0 } else { wt.ewt[i] };
                    wt.newton[i] = wt.ewt[i] * scale;
                }
                // Resolved in `Core::new` to one of the others or to this: index >= 2 out
                // of the error test, index 1 in full.
                AlgebraicControl::Auto => {
                    wt.err[i] = if kind.level() >= 2 { 0.0 } else { wt.ewt[i] };
                    wt.newton[i] = wt.ewt[i] * scale;
                }
            }
        }
    }

    /// One accepted step, with retries (IDAStep).
    fn ida_step(&mut self) -> Result<(), SolverError> {
        let tsave = self.core.t;
        let mut ncf = 0usize;
        let mut nef = 0usize;
        if let Some(hl) = self.core.prob.max_step(tsave, &self.hist.phi[0]) {
            if self.ctl.hh > hl {
                self.ctl.hh = hl;
            }
        }
        if let Some(ts) = self.core.tstop {
            if tsave + self.ctl.hh > ts {
                self.ctl.hh = ts - tsave;
            }
        }
        loop {
            self.save_history();
            self.set_coeffs();
            self.core.t = self.core.snap_to_stop(tsave + self.ctl.hh);
            self.set_step_weights();
            self.predict();
            let outcome = self.nonlinear_solve();
            let failure = match outcome {
                Ok(()) => {
                    let enorm_k = self.test_error();
                    if self.hist.ck * enorm_k > 1.0 {
                        nef += 1;
                        self.core.stats.error_test_failures += 1;
                        self.core.stats.rejected_steps += 1;
                        if nef >= self.core.opts.max_error_failures {
                            self.restore(tsave);
                            return Err(SolverError::ErrorTestFailure {
                                t: tsave,
                                h: self.ctl.hh,
                                failures: nef,
                                worst: self.core.worst_components(&self.work.ee, &self.wt.err),
                            });
                        }
                        self.restore(tsave);
                        self.ctl.phase = 1;
                        let ctl = &mut self.ctl;
                        // IDAHandleNFlag: the order of the failed attempt's estimate, then
                        // a fixed cut, then order 1.
                        let rr = if nef == 1 {
                            let err_knew = if ctl.knew == ctl.kk {
                                ctl.err_k
                            } else {
                                ctl.err_km1
                            };
                            ctl.kk = ctl.knew;
                            (ETA_EF_SAFETY
                                * (2.0 * err_knew + ERR_BIAS).powf(-1.0 / (ctl.kk as f64 + 1.0)))
                            .clamp(ETA_MIN_EF, ETA_LOW)
                        } else if nef == 2 {
                            ctl.kk = ctl.knew;
                            ETA_MIN_EF
                        } else {
                            ctl.kk = 1;
                            ETA_MIN_EF
                        };
                        ctl.hh *= rr;
                        None
                    } else {
                        self.complete_step();
                        return Ok(());
                    }
                }
                Err(f) => Some(f),
            };
            if let Some(f) = failure {
                ncf += 1;
                self.core.stats.convergence_failures += 1;
                self.core.stats.rejected_steps += 1;
                self.restore(tsave);
                self.ctl.phase = 1;
                if ncf >= self.core.opts.max_convergence_failures {
                    return Err(match f {
                        StepFail::Singular(s) => SolverError::SingularMatrix {
                            t: tsave,
                            h: self.ctl.hh,
                            detail: self.core.describe_singular(&s),
                        },
                        StepFail::NonFinite(eqs) => SolverError::NonFiniteResidual {
                            t: tsave,
                            equations: eqs,
                        },
                        StepFail::Convergence(worst) => SolverError::ConvergenceFailure {
                            t: tsave,
                            h: self.ctl.hh,
                            failures: ncf,
                            worst,
                        },
                    });
                }
                self.ctl.hh *= ETA_CF;
                self.nls.jac_valid = false;
            }
            let hh = self.ctl.hh;
            if hh.abs() < self.core.opts.h_min
                || hh.abs() <= HMIN_UROUNDS * UROUND * tsave.abs().max(1.0)
            {
                return Err(SolverError::StepTooSmall {
                    t: tsave,
                    h: hh,
                    h_min: self.core.opts.h_min,
                });
            }
        }
    }

    fn save_history(&mut self) {
        let h = &mut self.hist;
        let top = (self.ctl.kk + 1).min(MAXORD + 1);
        for j in 0..=top {
            h.backup_phi[j].copy_from_slice(&h.phi[j]);
        }
        h.backup_psi = h.psi;
    }

    fn restore(&mut self, tsave: f64) {
        self.core.t = tsave;
        let h = &mut self.hist;
        let top = (self.ctl.kk + 1).min(MAXORD + 1);
        for j in 0..=top {
            h.phi[j].copy_from_slice(&h.backup_phi[j]);
        }
        h.psi = h.backup_psi;
    }

    /// Coefficients of the step about to be taken (IDASetCoeffs).
    fn set_coeffs(&mut self) {
        let (kk, hh) = (self.ctl.kk, self.ctl.hh);
        let hused = self.core.h_used;
        let ctl = &mut self.ctl;
        let h = &mut self.hist;
        if hh != hused || kk != ctl.kused {
            ctl.ns = 0;
        }
        ctl.ns = (ctl.ns + 1).min(ctl.kused + 2);
        match self.core.opts.method {
            // (`new` refuses Radau5.)
            Method::Variable | Method::Radau5 => {
                if kk + 1 >= ctl.ns {
                    h.beta[0] = 1.0;
                    h.alpha[0] = 1.0;
                    let mut temp1 = hh;
                    h.gamma[0] = 0.0;
                    h.sigma[0] = 1.0;
                    for i in 1..=kk {
                        let temp2 = h.psi[i - 1];
                        h.psi[i - 1] = temp1;
                        h.beta[i] = h.beta[i - 1] * h.psi[i - 1] / temp2;
                        temp1 = temp2 + hh;
                        h.alpha[i] = hh / temp1;
                        h.sigma[i] = i as f64 * h.sigma[i - 1] * h.alpha[i];
                        h.gamma[i] = h.gamma[i - 1] + h.alpha[i - 1] / hh;
                    }
                    h.psi[kk] = temp1;
                }
                if ctl.ns <= kk {
                    for i in ctl.ns..=kk {
                        let b = h.beta[i];
                        for v in h.phi[i].iter_mut() {
                            *v *= b;
                        }
                    }
                }
            }
            Method::FixedCoefficient => {
                if ctl.kused > 0 && hh != hused {
                    rescale_differences(&mut h.phi, kk, hh / hused);
                }
                h.beta[0] = 1.0;
                h.alpha[0] = 1.0;
                h.gamma[0] = 0.0;
                h.sigma[0] = 1.0;
                for i in 0..=kk {
                    h.psi[i] = (i as f64 + 1.0) * hh;
                }
                for i in 1..=kk {
                    h.beta[i] = 1.0;
                    h.alpha[i] = 1.0 / (i as f64 + 1.0);
                    h.sigma[i] = i as f64 * h.sigma[i - 1] * h.alpha[i];
                    h.gamma[i] = h.gamma[i - 1] + h.alpha[i - 1] / hh;
                }
            }
        }
        let mut alphas = 0.0;
        let mut alpha0 = 0.0;
        for i in 0..kk {
            alphas -= 1.0 / (i as f64 + 1.0);
            alpha0 -= h.alpha[i];
        }
        h.cjlast = h.cj;
        h.cj = -alphas / hh;
        h.ck = (h.alpha[kk] + alphas - alpha0).abs().max(h.alpha[kk]);
    }

    /// Predictor: the history polynomial evaluated at the new time (IDAPredict).
    fn predict(&mut self) {
        let w = &mut self.work;
        w.ypred.copy_from_slice(&self.hist.phi[0]);
        w.yppred.fill(0.0);
        for j in 1..=self.ctl.kk {
            let g = self.hist.gamma[j];
            for ((yp, ypp), p) in w
                .ypred
                .iter_mut()
                .zip(w.yppred.iter_mut())
                .zip(&self.hist.phi[j])
            {
                *yp += p;
                *ypp += g * p;
            }
        }
    }
}

impl<'a, P: DaeProblem + ?Sized> DaeMethod<'a, P> for Bdf<'a, P> {
    fn core(&self) -> &Core<'a, P> {
        &self.core
    }

    fn core_mut(&mut self) -> &mut Core<'a, P> {
        &mut self.core
    }

    /// First step size and history (IDA's IDAInitialSetup and the start of IDASolve).
    fn start(&mut self, tout: f64) -> Result<(), SolverError> {
        let c = &self.core;
        let mut h = c.initial_step(tout, &self.hist.phi[1], &self.wt.ewt);
        if let Some(ts) = c.tstop {
            h = h.min(ts - c.t);
        }
        if h <= 0.0 {
            return Err(SolverError::StepTooSmall {
                t: c.t,
                h,
                h_min: c.opts.h_min,
            });
        }
        for v in self.hist.phi[1].iter_mut() {
            *v *= h;
        }
        self.ctl.hh = h;
        self.hist.psi[0] = h;
        self.hist.cj = 1.0 / h;
        self.hist.cjlast = self.hist.cj;
        self.ctl.kk = 1;
        self.ctl.kused = 0;
        self.core.h_used = 0.0;
        self.ctl.ns = 0;
        self.ctl.phase = 0;
        Ok(())
    }

    fn step(&mut self) -> Result<(), SolverError> {
        debug_assert!(self.core.started, "`advance` starts the integration");
        self.ida_step()
    }

    /// Solution and derivative at `t` from the interpolating polynomial of the last step
    /// (IDAGetSolution). Accurate for t in [tn - hused, tn].
    fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        let h = &self.hist;
        let kord = self.ctl.kused.max(1);
        let delt = t - self.core.t;
        let mut c = 1.0;
        let mut d = 0.0;
        let mut gam = delt / h.psi[0];
        y.copy_from_slice(&h.phi[0]);
        yp.fill(0.0);
        for j in 1..=kord {
            d = d * gam + c / h.psi[j - 1];
            c *= gam;
            gam = (delt + h.psi[j - 1]) / h.psi[j];
            for i in 0..self.core.n {
                y[i] += c * h.phi[j][i];
                yp[i] += d * h.phi[j][i];
            }
        }
    }

    /// IDA's event tolerance takes the step to be attempted next (hh).
    fn root_step(&self) -> Option<f64> {
        Some(self.ctl.hh)
    }
}
