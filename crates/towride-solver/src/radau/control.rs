//! Tolerances, weights, the filtered error estimate and the step-size controller of
//! RADAU5 (Hairer & Wanner II, IV.8, (8.19)-(8.25); RADAU5's RADAU5 set-up, ESTRAD and
//! the step-size code of RADCOR).

use super::tableau::DD;
use super::Radau5;
use crate::error::SolverError;
use crate::method::wrms;
use crate::options::{AlgebraicControl, RadauOptions, SolverOptions};
use crate::problem::DaeProblem;

const UROUND: f64 = f64::EPSILON;
/// RADAU5 works with rtol' = 0.1 rtol^(2/3) and atol' = atol rtol'/rtol: its error
/// estimate is of order 3 (local error O(h^4)) for a method of order 5, and this keeps
/// the global error near the tolerance asked for (RADAU5, "CHECK AND CHANGE THE
/// TOLERANCES").
const TOL_FACTOR: f64 = 0.1;
const TOL_EXPONENT: f64 = 2.0 / 3.0;
/// FNEWT = max(10 uround / rtol', min(0.03, sqrt(rtol'))) (RADAU5's default).
const FNEWT_UROUNDS: f64 = 10.0;
const FNEWT_MAX: f64 = 0.03;
/// Safety factor of the step prediction (RADAU5's SAFE, WORK(2)).
const SAFE: f64 = 0.9;
/// The new step lies within [h / FACL, h / FACR] = [h/5, 8 h] (RADAU5's WORK(8), WORK(9)).
const FACL: f64 = 5.0;
const FACR: f64 = 1.0 / 8.0;
/// Error estimates below this count as this (RADAU5: ERR = MAX(..., 1.D-10)).
const ERR_FLOOR: f64 = 1e-10;
/// Gustafsson's controller uses max(err, 1e-2) of the previous step.
const ERR_ACC_FLOOR: f64 = 1e-2;
/// Exponent of the controller: the estimate is O(h^4).
const ERR_EXPONENT: f64 = 0.25;

/// (rtol', atol') as RADAU5 uses them inside. With rtol = 0 the transformation is
/// applied to each atol.
pub(super) fn internal_tolerances(opts: &SolverOptions, n: usize) -> (f64, Vec<f64>) {
    let rtol = opts.rtol;
    let tr = |x: f64| TOL_FACTOR * x.powf(TOL_EXPONENT);
    if rtol > 0.0 {
        let r = tr(rtol);
        (r, (0..n).map(|i| opts.atol_of(i) * r / rtol).collect())
    } else {
        (0.0, (0..n).map(|i| tr(opts.atol_of(i))).collect())
    }
}

/// RADAU5's FNEWT from the internal relative tolerance (the smallest atol' when rtol = 0).
pub(super) fn newton_stop(rtol: f64, atol: &[f64]) -> f64 {
    let tol = if rtol > 0.0 {
        rtol
    } else {
        atol.iter().copied().fold(f64::INFINITY, f64::min)
    };
    (FNEWT_UROUNDS * UROUND / tol).max(FNEWT_MAX.min(tol.sqrt()))
}

/// h / h_new from the error estimate and the Newton iterations used:
/// fac = min(SAFE, SAFE (1 + 2 NIT) / (newt + 2 NIT)), quot = err^(1/4) / fac in
/// [FACR, FACL] (RADAU5, "COMPUTATION OF HNEW").
pub(super) fn step_quotient(err: f64, newt: usize, r: &RadauOptions) -> f64 {
    let nit = r.newton_iters as f64;
    let fac = SAFE.min(SAFE * (1.0 + 2.0 * nit) / (newt as f64 + 2.0 * nit));
    (err.powf(ERR_EXPONENT) / fac).clamp(FACR, FACL)
}

/// Gustafsson's predictive controller on an accepted step (Hairer & Wanner II, IV.8,
/// (8.25)): the smaller of the two proposals. Updates the remembered step and error.
pub(super) fn gustafsson<P: DaeProblem + ?Sized>(
    s: &mut Radau5<'_, P>,
    err: f64,
    hnew: f64,
) -> f64 {
    let mut hnew = hnew;
    if s.core.stats.steps >= 1 {
        let facgus = (s.ctl.h_acc / s.h) * (err * err / s.ctl.err_acc).powf(ERR_EXPONENT) / SAFE;
        let facgus = facgus.clamp(FACR, FACL);
        hnew = hnew.min(s.h / facgus);
    }
    s.ctl.h_acc = s.h;
    s.ctl.err_acc = err.max(ERR_ACC_FLOOR);
    hnew
}

impl<P: DaeProblem + ?Sized> Radau5<'_, P> {
    /// Error weights 1/(atol' + rtol' |y|) at the current state; a vector-valued unknown
    /// takes the vector's length for |y| (`vector_error_weights`).
    pub(super) fn set_ewt(&mut self) {
        let atol = &self.atol;
        self.wt
            .set_ewt(&self.y, self.rtol, |i| atol[i], &self.core.groups);
    }

    /// Weights of the step: index-k unknowns get h^(k-1) (RADAU5 divides their SCAL by h
    /// and h^2), in the Newton norm always and in the error norm as `algebraic` says; the
    /// Newton matrix's columns are scaled as the BDF's are.
    pub(super) fn set_step_weights(&mut self) {
        let h = self.h.abs();
        let hs = h.min(1.0);
        let (c, wt) = (&self.core, &mut self.wt);
        for i in 0..c.n {
            let kind = c.kinds[i];
            let level = kind.level() - 1;
            let scale = h.powi(level);
            wt.col_scale[i] = if c.opts.scale_newton_matrix {
                hs.powi(-level)
            } else {
                1.0
            };
            let e = wt.ewt[i];
            let (err, newton) = match c.algebraic {
                AlgebraicControl::Full => (e, e),
                AlgebraicControl::Scaled => (e * scale, e * scale),
                AlgebraicControl::Exclude => (if kind.is_algebraic() { 0.0 } else { e }, e * scale),
                // Resolved in `Core::new`: index >= 2 out of the error test.
                AlgebraicControl::Auto => (if level >= 1 { 0.0 } else { e }, e * scale),
            };
            wt.err[i] = err;
            wt.newton[i] = newton;
        }
    }

    /// The embedded error estimate filtered by (J_y + (gamma/h) J_y')^-1 and its weighted
    /// RMS norm (ESTRAD). For M y' = f RADAU5 solves
    /// (gamma/h M - J) e = f(t0, y0) + M v with v = sum_i (DD_i/h) Z_i. Both right-hand
    /// sides are -F(t0, y0, -v) for F = M y' - f, which is what is evaluated here (one
    /// residual, as RADAU5's one f): exact for every F linear in y'. After a rejected or
    /// a first step an estimate above 1 is filtered once more, with f at y0 + e
    /// (Hairer & Wanner II, (8.22)): -F(t0, y0 + e, -v).
    pub(super) fn error_estimate(&mut self) -> Result<f64, SolverError> {
        let hinv = 1.0 / self.h;
        let st = &mut self.st;
        for i in 0..self.core.n {
            st.yps[i] = -hinv * (DD[0] * st.z[0][i] + DD[1] * st.z[1][i] + DD[2] * st.z[2][i]);
        }
        self.filtered_estimate(false)?;
        let mut err = self.error_norm();
        if err >= 1.0 && (self.ctl.first || self.ctl.reject) {
            self.filtered_estimate(true)?;
            err = self.error_norm();
        }
        Ok(err)
    }

    /// err_vec = -(J_y + (gamma/h) J_y')^-1 F(t0, y0 [+ err_vec], -v), -v in `yps`.
    fn filtered_estimate(&mut self, again: bool) -> Result<(), SolverError> {
        let (c, st) = (&mut self.core, &mut self.st);
        for i in 0..c.n {
            st.ys[i] = if again {
                self.y[i] + st.err_vec[i]
            } else {
                self.y[i]
            };
        }
        c.prob.residual(c.t, &st.ys, &st.yps, &mut st.res);
        c.stats.residual_evals += 1;
        if let Some(eqs) = c.non_finite(&st.res) {
            return Err(SolverError::NonFiniteResidual {
                t: c.t,
                equations: eqs,
            });
        }
        for (e, r) in st.err_vec.iter_mut().zip(&st.res) {
            *e = -r;
        }
        let mut e = std::mem::take(&mut self.st.err_vec);
        let solved = self.solve_real(&mut e);
        self.st.err_vec = e;
        solved.map_err(|s| SolverError::SingularMatrix {
            t: self.core.t,
            h: self.h,
            detail: s.detail,
        })
    }

    fn error_norm(&self) -> f64 {
        wrms(&self.st.err_vec, &self.wt.err).max(ERR_FLOOR)
    }
}
