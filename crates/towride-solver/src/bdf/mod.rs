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
use super::options::{
    AlgebraicControl, JacobianSource, LinearSolver, Method, SolverOptions, Stats,
};
use super::problem::{DaeProblem, VarKind};
use super::roots::Roots;

mod control;
mod history;
mod newton;

use history::rescale_differences;

pub(crate) const MAXORD: usize = 5;
const UROUND: f64 = f64::EPSILON;

/// What a call to [`Bdf::advance`] ended with.
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

enum StepFail {
    Convergence(String),
    Singular(Singular),
    NonFinite(String),
}

/// The BDF integrator bound to one problem.
pub struct Bdf<'a, P: DaeProblem + ?Sized> {
    prob: &'a P,
    opts: SolverOptions,
    n: usize,
    kinds: Vec<VarKind>,
    /// Error control of the algebraic unknowns with `Auto` resolved (`Auto` stays only
    /// for problems of index <= 2, meaning: index-2 unknowns out of the error test).
    algebraic: AlgebraicControl,
    // History and coefficients (IDA names).
    phi: Vec<Vec<f64>>,
    psi: [f64; MAXORD + 2],
    alpha: [f64; MAXORD + 2],
    beta: [f64; MAXORD + 2],
    sigma: [f64; MAXORD + 2],
    gamma: [f64; MAXORD + 2],
    tn: f64,
    hh: f64,
    hused: f64,
    kk: usize,
    kused: usize,
    knew: usize,
    ns: usize,
    phase: u8,
    cj: f64,
    cjold: f64,
    cjlast: f64,
    cjratio: f64,
    ck: f64,
    ss: f64,
    oldnrm: f64,
    err_k: f64,
    err_km1: f64,
    started: bool,
    tstop: Option<f64>,
    // Work vectors.
    ewt: Vec<f64>,
    /// Vector-valued unknowns weighted by their length (empty when the option is off).
    groups: Vec<std::ops::Range<usize>>,
    wt_err: Vec<f64>,
    wt_newton: Vec<f64>,
    col_scale: Vec<f64>,
    yy: Vec<f64>,
    yp: Vec<f64>,
    ypred: Vec<f64>,
    yppred: Vec<f64>,
    ee: Vec<f64>,
    delta: Vec<f64>,
    res: Vec<f64>,
    backup_phi: Vec<Vec<f64>>,
    /// Work vector for the error estimates at neighbouring orders.
    scratch: Vec<f64>,
    backup_psi: [f64; MAXORD + 2],
    jac: NewtonMatrix,
    /// Jacobian evaluation (analytic or finite differences) and its buffers.
    jeval: JacobianEval,
    jac_valid: bool,
    jac_age: usize,
    /// The state the iteration matrix was evaluated at (for the problem's frame
    /// transport, and for dF/dy' when it is recombined).
    y_built: Vec<f64>,
    yp_built: Vec<f64>,
    t_built: f64,
    /// Whether the problem's frame transport is used.
    transport: bool,
    /// Event location.
    roots: Roots,
    stats: Stats,
    /// Accepted steps in which each unknown dominated the error estimate.
    limiter_counts: Vec<usize>,
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
        let n = prob.size();
        opts.validate(n)?;
        if opts.method == Method::Radau5 {
            return Err(SolverError::InvalidSettings {
                field: "method".into(),
                why: "radau5 is not a BDF variant; integrate through `Integrator`, which \
                      chooses by the method"
                    .into(),
            });
        }
        let kinds = crate::problem::check_start(prob, t0, y0, yp0)?;
        let algebraic = match opts.algebraic {
            AlgebraicControl::Auto if kinds.contains(&VarKind::Index3) => AlgebraicControl::Scaled,
            a => a,
        };
        let pattern = prob.jacobian_pattern();
        let dense = match opts.linear_solver {
            LinearSolver::Dense => true,
            LinearSolver::Sparse => false,
            LinearSolver::Auto => pattern.is_none() || n < opts.dense_limit,
        };
        let jac = NewtonMatrix::new(n, pattern, dense)?;
        let mut phi = vec![vec![0.0; n]; MAXORD + 2];
        phi[0].copy_from_slice(y0);
        phi[1].copy_from_slice(yp0); // scaled by h once the first step size is known
        let analytic_ok = opts.jacobian == JacobianSource::Auto;
        let mut s = Self {
            prob,
            n,
            kinds,
            algebraic,
            phi,
            psi: [0.0; MAXORD + 2],
            alpha: [0.0; MAXORD + 2],
            beta: [0.0; MAXORD + 2],
            sigma: [0.0; MAXORD + 2],
            gamma: [0.0; MAXORD + 2],
            tn: t0,
            hh: 0.0,
            hused: 0.0,
            kk: 1,
            kused: 0,
            knew: 1,
            ns: 0,
            phase: 0,
            cj: 0.0,
            cjold: 0.0,
            cjlast: 0.0,
            cjratio: 1.0,
            ck: 1.0,
            ss: 20.0,
            oldnrm: 0.0,
            err_k: 0.0,
            err_km1: 0.0,
            started: false,
            tstop: None,
            ewt: vec![0.0; n],
            // Not with fixed coefficients: their step changes interpolate the history
            // onto an equal grid, and the looser weights let the spinning wheels' history
            // grow an interpolation error that no step cut removes (measured: the default
            // scene then fails at every tolerance).
            groups: if opts.vector_error_weights && opts.method == Method::Variable {
                prob.magnitude_groups()
            } else {
                Vec::new()
            },
            wt_err: vec![0.0; n],
            wt_newton: vec![0.0; n],
            col_scale: vec![1.0; n],
            yy: y0.to_vec(),
            yp: yp0.to_vec(),
            ypred: vec![0.0; n],
            yppred: vec![0.0; n],
            ee: vec![0.0; n],
            delta: vec![0.0; n],
            res: vec![0.0; n],
            backup_phi: vec![vec![0.0; n]; MAXORD + 2],
            scratch: vec![0.0; n],
            backup_psi: [0.0; MAXORD + 2],
            jac,
            jeval: JacobianEval::new(analytic_ok),
            jac_valid: false,
            jac_age: 0,
            y_built: vec![0.0; n],
            yp_built: vec![0.0; n],
            t_built: t0,
            transport: opts.matrix_transport && prob.has_transport(),
            roots: Roots::default(),
            stats: Stats::default(),
            limiter_counts: vec![0; n],
            opts,
        };
        s.set_ewt();
        s.roots = Roots::new(prob, t0, y0, yp0, &mut s.stats.root_evals);
        Ok(s)
    }

    /// Never step past `tstop` (for example the end of the road or of the run).
    pub fn set_stop_time(&mut self, tstop: f64) {
        self.tstop = Some(tstop);
    }

    /// Current internal time (the end of the last accepted step).
    pub fn t(&self) -> f64 {
        self.tn
    }

    /// Counters of the integration so far.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The `k` unknowns that dominated the error estimate in the most accepted steps, by
    /// name, with their step counts: what sets the step size.
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

    fn count_limiter(&mut self) {
        let worst = (0..self.n).max_by(|&a, &b| {
            (self.ee[a] * self.wt_err[a])
                .abs()
                .total_cmp(&(self.ee[b] * self.wt_err[b]).abs())
        });
        if let Some(i) = worst {
            self.limiter_counts[i] += 1;
        }
    }

    /// The settings the integrator runs with.
    pub fn options(&self) -> &SolverOptions {
        &self.opts
    }

    /// True when the dense (not sparse) LU path is in use.
    pub fn uses_dense_lu(&self) -> bool {
        self.jac.is_dense()
    }

    /// Structural non-zeros of the iteration matrix.
    pub fn jacobian_nnz(&self) -> usize {
        self.jac.nnz()
    }

    /// Integrates until the internal time reaches `tout` or an event function changes sign.
    pub fn advance(&mut self, tout: f64) -> Result<Advance, SolverError> {
        if !tout.is_finite() {
            return Err(SolverError::BadOutputTime { tout, t: self.tn });
        }
        if !self.started {
            self.start(tout)?;
        } else if tout < self.tn - self.hused {
            return Err(SolverError::BadOutputTime { tout, t: self.tn });
        }
        // A root between the last reported root and tn may still be pending.
        if let Some(r) = self.check_roots() {
            return Ok(r);
        }
        crate::integrator::drive(self, tout)
    }

    /// First step size and history (IDA's IDAInitialSetup and the start of IDASolve).
    fn start(&mut self, tout: f64) -> Result<(), SolverError> {
        let tdist = (tout - self.tn).abs();
        if tdist == 0.0 {
            return Err(SolverError::BadOutputTime { tout, t: self.tn });
        }
        let mut h = match self.opts.h_init {
            Some(h) => h,
            None => {
                let mut h = 0.001 * tdist;
                // ||y'0|| over unknowns whose derivative is meaningful.
                let mut sum = 0.0;
                for i in 0..self.n {
                    if self.kinds[i] == VarKind::Differential {
                        sum += (self.phi[1][i] * self.ewt[i]).powi(2);
                    }
                }
                let ypnorm = (sum / self.n as f64).sqrt();
                if ypnorm > 0.5 / h {
                    h = 0.5 / ypnorm;
                }
                h
            }
        };
        h = h.min(self.opts.h_max);
        if let Some(ts) = self.tstop {
            h = h.min(ts - self.tn);
        }
        if h <= 0.0 {
            return Err(SolverError::StepTooSmall {
                t: self.tn,
                h,
                h_min: self.opts.h_min,
            });
        }
        for v in self.phi[1].iter_mut() {
            *v *= h;
        }
        self.hh = h;
        self.psi[0] = h;
        self.cj = 1.0 / h;
        self.cjlast = self.cj;
        self.kk = 1;
        self.kused = 0;
        self.hused = 0.0;
        self.ns = 0;
        self.phase = 0;
        self.started = true;
        Ok(())
    }

    /// Restarts the integration at a new consistent state (after a discontinuity).
    pub fn reinit(&mut self, t: f64, y: &[f64], yp: &[f64]) -> Result<(), SolverError> {
        if y.iter().chain(yp).any(|v| !v.is_finite()) {
            return Err(SolverError::NonFiniteInitial {
                name: "reinit state".into(),
                value: f64::NAN,
            });
        }
        self.tn = t;
        self.phi[0].copy_from_slice(y);
        self.phi[1].copy_from_slice(yp);
        self.started = false;
        self.jac_valid = false;
        self.set_ewt();
        self.roots
            .restart(self.prob, t, y, yp, &mut self.stats.root_evals);
        Ok(())
    }

    fn set_ewt(&mut self) {
        for i in 0..self.n {
            self.ewt[i] = 1.0 / (self.opts.rtol * self.phi[0][i].abs() + self.opts.atol_of(i));
        }
        for g in &self.groups {
            let len = self.phi[0][g.clone()]
                .iter()
                .map(|y| y * y)
                .sum::<f64>()
                .sqrt();
            for i in g.clone() {
                self.ewt[i] = 1.0 / (self.opts.rtol * len + self.opts.atol_of(i));
            }
        }
    }

    /// Error-test and Newton weights for the current step size (index-k unknowns get
    /// h^(k-1), Hairer & Wanner II, VII.3).
    fn set_step_weights(&mut self) {
        let hs = self.hh.abs().min(1.0);
        for i in 0..self.n {
            let kind = self.kinds[i];
            let scale = hs.powi(kind.level() - 1);
            // Unknowns of index k are solved for as h^(k-1) times their correction, which
            // with row equilibration keeps cond(J) bounded as h -> 0.
            self.col_scale[i] = if self.opts.scale_newton_matrix {
                1.0 / scale
            } else {
                1.0
            };
            match self.algebraic {
                AlgebraicControl::Full => {
                    self.wt_err[i] = self.ewt[i];
                    self.wt_newton[i] = self.ewt[i];
                }
                AlgebraicControl::Scaled => {
                    self.wt_err[i] = self.ewt[i] * scale;
                    self.wt_newton[i] = self.ewt[i] * scale;
                }
                AlgebraicControl::Exclude => {
                    self.wt_err[i] = if kind.is_algebraic() {
                        0.0
                    } else {
                        self.ewt[i]
                    };
                    self.wt_newton[i] = self.ewt[i] * scale;
                }
                // Resolved in `new` to one of the others or to this: index >= 2 out of
                // the error test, index 1 in full.
                AlgebraicControl::Auto => {
                    self.wt_err[i] = if kind.level() >= 2 { 0.0 } else { self.ewt[i] };
                    self.wt_newton[i] = self.ewt[i] * scale;
                }
            }
        }
    }

    fn wrms(&self, v: &[f64], w: &[f64]) -> f64 {
        let s: f64 = v.iter().zip(w).map(|(a, b)| (a * b) * (a * b)).sum();
        (s / self.n as f64).sqrt()
    }

    /// One accepted step, with retries (IDAStep).
    fn step(&mut self) -> Result<(), SolverError> {
        let tsave = self.tn;
        let mut ncf = 0usize;
        let mut nef = 0usize;
        if let Some(hl) = self.prob.max_step(self.tn, &self.phi[0]) {
            if self.hh > hl {
                self.hh = hl;
            }
        }
        if let Some(ts) = self.tstop {
            if self.tn + self.hh > ts {
                self.hh = ts - self.tn;
            }
        }
        loop {
            self.save_history();
            self.set_coeffs();
            self.tn = tsave + self.hh;
            if let Some(ts) = self.tstop {
                if (self.tn - ts).abs() <= 4.0 * UROUND * ts.abs().max(1.0) {
                    self.tn = ts;
                }
            }
            self.set_step_weights();
            self.predict();
            let outcome = self.nonlinear_solve();
            let failure = match outcome {
                Ok(()) => {
                    let enorm_k = self.test_error();
                    if self.ck * enorm_k > 1.0 {
                        nef += 1;
                        self.stats.error_test_failures += 1;
                        self.stats.rejected_steps += 1;
                        if nef >= self.opts.max_error_failures {
                            self.restore(tsave);
                            return Err(SolverError::ErrorTestFailure {
                                t: tsave,
                                h: self.hh,
                                failures: nef,
                                worst: self
                                    .worst_components(&self.ee.clone(), &self.wt_err.clone()),
                            });
                        }
                        self.restore(tsave);
                        self.phase = 1;
                        let rr = if nef == 1 {
                            let err_knew = if self.knew == self.kk {
                                self.err_k
                            } else {
                                self.err_km1
                            };
                            self.kk = self.knew;
                            (0.9 * (2.0 * err_knew + 0.0001).powf(-1.0 / (self.kk as f64 + 1.0)))
                                .clamp(0.25, 0.9)
                        } else if nef == 2 {
                            self.kk = self.knew;
                            0.25
                        } else {
                            self.kk = 1;
                            0.25
                        };
                        self.hh *= rr;
                        None
                    } else {
                        self.count_limiter();
                        self.complete_step();
                        return Ok(());
                    }
                }
                Err(f) => Some(f),
            };
            if let Some(f) = failure {
                ncf += 1;
                self.stats.convergence_failures += 1;
                self.stats.rejected_steps += 1;
                self.restore(tsave);
                self.phase = 1;
                if ncf >= self.opts.max_convergence_failures {
                    return Err(match f {
                        StepFail::Singular(s) => SolverError::SingularMatrix {
                            t: tsave,
                            h: self.hh,
                            detail: self.describe_singular(&s),
                        },
                        StepFail::NonFinite(eqs) => SolverError::NonFiniteResidual {
                            t: tsave,
                            equations: eqs,
                        },
                        StepFail::Convergence(worst) => SolverError::ConvergenceFailure {
                            t: tsave,
                            h: self.hh,
                            failures: ncf,
                            worst,
                        },
                    });
                }
                self.hh *= 0.25;
                self.jac_valid = false;
            }
            if self.hh.abs() < self.opts.h_min
                || self.hh.abs() <= 10.0 * UROUND * tsave.abs().max(1.0)
            {
                return Err(SolverError::StepTooSmall {
                    t: tsave,
                    h: self.hh,
                    h_min: self.opts.h_min,
                });
            }
        }
    }

    fn save_history(&mut self) {
        let top = (self.kk + 1).min(MAXORD + 1);
        for j in 0..=top {
            self.backup_phi[j].copy_from_slice(&self.phi[j]);
        }
        self.backup_psi = self.psi;
    }

    fn restore(&mut self, tsave: f64) {
        self.tn = tsave;
        let top = (self.kk + 1).min(MAXORD + 1);
        for j in 0..=top {
            self.phi[j].copy_from_slice(&self.backup_phi[j]);
        }
        self.psi = self.backup_psi;
    }

    /// Coefficients of the step about to be taken (IDASetCoeffs).
    fn set_coeffs(&mut self) {
        let (kk, hh) = (self.kk, self.hh);
        if hh != self.hused || kk != self.kused {
            self.ns = 0;
        }
        self.ns = (self.ns + 1).min(self.kused + 2);
        match self.opts.method {
            // (`new` refuses Radau5.)
            Method::Variable | Method::Radau5 => {
                if kk + 1 >= self.ns {
                    self.beta[0] = 1.0;
                    self.alpha[0] = 1.0;
                    let mut temp1 = hh;
                    self.gamma[0] = 0.0;
                    self.sigma[0] = 1.0;
                    for i in 1..=kk {
                        let temp2 = self.psi[i - 1];
                        self.psi[i - 1] = temp1;
                        self.beta[i] = self.beta[i - 1] * self.psi[i - 1] / temp2;
                        temp1 = temp2 + hh;
                        self.alpha[i] = hh / temp1;
                        self.sigma[i] = i as f64 * self.sigma[i - 1] * self.alpha[i];
                        self.gamma[i] = self.gamma[i - 1] + self.alpha[i - 1] / hh;
                    }
                    self.psi[kk] = temp1;
                }
                if self.ns <= kk {
                    for i in self.ns..=kk {
                        let b = self.beta[i];
                        for v in self.phi[i].iter_mut() {
                            *v *= b;
                        }
                    }
                }
            }
            Method::FixedCoefficient => {
                if self.kused > 0 && hh != self.hused {
                    rescale_differences(&mut self.phi, kk, hh / self.hused);
                }
                self.beta[0] = 1.0;
                self.alpha[0] = 1.0;
                self.gamma[0] = 0.0;
                self.sigma[0] = 1.0;
                for i in 0..=kk {
                    self.psi[i] = (i as f64 + 1.0) * hh;
                }
                for i in 1..=kk {
                    self.beta[i] = 1.0;
                    self.alpha[i] = 1.0 / (i as f64 + 1.0);
                    self.sigma[i] = i as f64 * self.sigma[i - 1] * self.alpha[i];
                    self.gamma[i] = self.gamma[i - 1] + self.alpha[i - 1] / hh;
                }
            }
        }
        let mut alphas = 0.0;
        let mut alpha0 = 0.0;
        for i in 0..kk {
            alphas -= 1.0 / (i as f64 + 1.0);
            alpha0 -= self.alpha[i];
        }
        self.cjlast = self.cj;
        self.cj = -alphas / hh;
        self.ck = (self.alpha[kk] + alphas - alpha0).abs().max(self.alpha[kk]);
    }

    /// Predictor: the history polynomial evaluated at the new time (IDAPredict).
    fn predict(&mut self) {
        self.ypred.copy_from_slice(&self.phi[0]);
        self.yppred.fill(0.0);
        for j in 1..=self.kk {
            let g = self.gamma[j];
            for ((yp, ypp), p) in self
                .ypred
                .iter_mut()
                .zip(self.yppred.iter_mut())
                .zip(&self.phi[j])
            {
                *yp += p;
                *ypp += g * p;
            }
        }
    }

    /// Solution and derivative at `t` from the interpolating polynomial of the last step
    /// (IDAGetSolution). Accurate for t in [tn - hused, tn].
    pub fn interpolate(&self, t: f64, y: &mut [f64], yp: &mut [f64]) {
        let kord = self.kused.max(1);
        let delt = t - self.tn;
        let mut c = 1.0;
        let mut d = 0.0;
        let mut gam = delt / self.psi[0];
        y.copy_from_slice(&self.phi[0]);
        yp.fill(0.0);
        for j in 1..=kord {
            d = d * gam + c / self.psi[j - 1];
            c *= gam;
            gam = (delt + self.psi[j - 1]) / self.psi[j];
            for i in 0..self.n {
                y[i] += c * self.phi[j][i];
                yp[i] += d * self.phi[j][i];
            }
        }
    }

    /// Events over the last step, located on its interpolant.
    fn check_roots(&mut self) -> Option<Advance> {
        if self.roots.is_empty() || !self.started {
            return None;
        }
        let mut roots = std::mem::take(&mut self.roots);
        let mut evals = self.stats.root_evals;
        let found = roots.check(
            self.prob,
            self.tn,
            self.hh,
            &|t, y, yp| self.interpolate(t, y, yp),
            &mut evals,
        );
        self.stats.root_evals = evals;
        self.roots = roots;
        found
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

    fn describe_singular(&self, s: &Singular) -> String {
        let list = |idx: &[usize], name: &dyn Fn(usize) -> String| {
            idx.iter()
                .take(5)
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

impl<P: DaeProblem + ?Sized> crate::integrator::Stepping for Bdf<'_, P> {
    fn now(&self) -> f64 {
        self.tn
    }
    fn finish_at(&mut self, t: f64) {
        self.tn = t;
    }
    fn stop_time(&self) -> Option<f64> {
        self.tstop
    }
    fn max_steps(&self) -> usize {
        self.opts.max_steps
    }
    fn step(&mut self) -> Result<(), SolverError> {
        Bdf::step(self)
    }
    fn check_roots(&mut self) -> Option<Advance> {
        Bdf::check_roots(self)
    }
}
