//! Simplified Newton on the transformed stage equations (Hairer & Wanner II, IV.8,
//! (8.15)-(8.21); RADAU5's RADCOR loop at label 40 and SLVRAD): the iteration matrices,
//! their factorisation, the starting values and the convergence control.

use nalgebra::Complex;

use super::tableau::{ALPHA, BETA, C, GAMMA, T, TI};
use super::{Radau5, MAX_SINGULAR, UROUND};
use crate::error::SolverError;
use crate::linear::Singular;
use crate::problem::{DaeProblem, Transport};

/// Contraction rate at or above which the iteration counts as diverging (RADAU5: 0.99).
const THETA_DIVERGING: f64 = 0.99;
/// RADAU5's FACCON is carried from step to step damped by this power.
const FACCON_MEMORY: f64 = 0.8;
/// When convergence within the iteration budget is predicted to fail, the step is cut by
/// 0.8 qnewt^(-1/(4 + iterations left)), qnewt the predicted error over the tolerance,
/// clamped to [1e-4, 20] (RADAU5).
const SLOW_SAFETY: f64 = 0.8;
const SLOW_QNEWT_MIN: f64 = 1e-4;
const SLOW_QNEWT_MAX: f64 = 20.0;
/// A Newton failure (divergence, too many iterations, singular matrix, non-finite
/// residual) halves the step (RADAU5, label 78).
const FAILURE_CUT: f64 = 0.5;

/// Why a Newton iteration was given up.
pub(super) enum NewtonFail {
    /// Diverged or did not converge within the iterations allowed.
    Diverged,
    /// Converging, but too slowly to finish within the iterations allowed: the step
    /// factor RADAU5 predicts.
    Slow(f64),
    Singular(Singular),
    NonFinite(String),
}

impl<P: DaeProblem + ?Sized> Radau5<'_, P> {
    /// Evaluates the Jacobian when none is kept and factorises both iteration matrices
    /// for the current step when they were made for another (RADAU5, labels 10 and 20).
    pub(super) fn prepare_matrices(&mut self) -> Result<(), NewtonFail> {
        let evaluated = !self.mats.jac_valid;
        if evaluated {
            let cj = GAMMA / self.h;
            self.mats
                .jeval
                .eval(
                    self.core.prob,
                    &mut self.mats.jac,
                    self.core.t,
                    &self.y,
                    &self.yp,
                    cj,
                    self.h,
                    &self.wt.ewt,
                    true,
                    &mut self.core.stats,
                )
                .map_err(NewtonFail::NonFinite)?;
            self.mats.jac.keep_as_base(cj);
            if self.mats.jeval.analytic && !self.mats.jeval.yp_entries.is_empty() {
                self.mats.jac.set_yp_part(&self.mats.jeval.yp_entries);
            } else {
                // dF/dy' from a second evaluation at cj = 0 (a problem that does not
                // report it, or finite differences).
                self.mats
                    .jeval
                    .eval(
                        self.core.prob,
                        &mut self.mats.jac,
                        self.core.t,
                        &self.y,
                        &self.yp,
                        0.0,
                        self.h,
                        &self.wt.ewt,
                        false,
                        &mut self.core.stats,
                    )
                    .map_err(NewtonFail::NonFinite)?;
                self.mats.jac.take_yp_part();
            }
            self.mats.y_built.copy_from_slice(&self.y);
            self.mats.jac_valid = true;
            self.mats.jac_fresh = true;
            self.mats.h_factored = 0.0;
        }
        if self.mats.h_factored != self.h {
            self.mats.h_factored = 0.0;
            let why = &mut self.core.stats.matrix_rebuilds;
            if !evaluated {
                // A kept Jacobian for a new step: J_y + s J_y' recombined from its parts.
                why.step_change += 1;
                self.core.stats.matrix_recombinations += 1;
            } else if self.mats.slow_newton {
                why.convergence += 1;
            } else {
                why.invalid += 1;
            }
            let equilibrate = self.core.opts.scale_newton_matrix;
            self.mats.jac.recombine(GAMMA / self.h);
            self.core.stats.lu_factorizations += 1;
            let done = self.mats.jac.factor(&self.wt.col_scale, equilibrate);
            self.core.stats.lu_entries = self.mats.jac.lu_nnz().unwrap_or(0);
            done.map_err(NewtonFail::Singular)?;
            self.core.stats.complex_lu_factorizations += 1;
            let shift = Complex::new(ALPHA / self.h, BETA / self.h);
            self.mats
                .cjac
                .factor(&self.mats.jac, shift, &self.wt.col_scale, equilibrate)
                .map_err(NewtonFail::Singular)?;
            self.mats.h_factored = self.h;
        }
        Ok(())
    }

    /// Starting values: zero at the first step, else the collocation polynomial of the
    /// last step extrapolated (RADAU5 with STARTN = .FALSE.).
    pub(super) fn starting_values(&mut self) {
        if self.ctl.first {
            for k in 0..3 {
                self.st.z[k].fill(0.0);
                self.st.w[k].fill(0.0);
            }
            return;
        }
        let c3q = self.h / self.core.h_used;
        let cq = [C[0] * c3q, C[1] * c3q, c3q];
        let (c1m1, c2m1) = (C[0] - 1.0, C[1] - 1.0);
        for i in 0..self.core.n {
            let (a1, a2, a3) = (self.cont[1][i], self.cont[2][i], self.cont[3][i]);
            let mut zi = [0.0; 3];
            for k in 0..3 {
                zi[k] = cq[k] * (a1 + (cq[k] - c2m1) * (a2 + (cq[k] - c1m1) * a3));
                self.st.z[k][i] = zi[k];
            }
            for k in 0..3 {
                self.st.w[k][i] = TI[k][0] * zi[0] + TI[k][1] * zi[1] + TI[k][2] * zi[2];
            }
        }
    }

    /// Y'_k = (1/h) sum_j (A^-1)_kj Z_j into `yps`.
    pub(super) fn stage_derivative(&mut self, k: usize) {
        let a = self.ainv[k];
        let hinv = 1.0 / self.h;
        for i in 0..self.core.n {
            self.st.yps[i] =
                hinv * (a[0] * self.st.z[0][i] + a[1] * self.st.z[1][i] + a[2] * self.st.z[2][i]);
        }
    }

    /// The simplified Newton iteration; returns the iterations used.
    pub(super) fn newton(&mut self) -> Result<usize, NewtonFail> {
        let nit = self.core.opts.radau.newton_iters;
        self.ctl.faccon = self.ctl.faccon.max(UROUND).powf(FACCON_MEMORY);
        self.ctl.theta = self.core.opts.radau.jacobian_theta.abs();
        let (mut dynold, mut thqold) = (0.0, 0.0);
        let norm_n = (3 * self.core.n) as f64;
        for newt in 1..=nit {
            // Stage residuals G_k, transformed: dw_k = -sum_j TI_kj G_j.
            for k in 0..3 {
                self.st.dw[k].fill(0.0);
            }
            for j in 0..3 {
                for i in 0..self.core.n {
                    self.st.ys[i] = self.y[i] + self.st.z[j][i];
                }
                self.stage_derivative(j);
                let tj = self.core.t + C[j] * self.h;
                self.core
                    .prob
                    .residual(tj, &self.st.ys, &self.st.yps, &mut self.st.res);
                self.core.stats.residual_evals += 1;
                if let Some(bad) = self.core.non_finite(&self.st.res) {
                    return Err(NewtonFail::NonFinite(bad));
                }
                for k in 0..3 {
                    let c = TI[k][j];
                    for (d, r) in self.st.dw[k].iter_mut().zip(&self.st.res) {
                        *d -= c * r;
                    }
                }
            }
            self.solve_stages().map_err(NewtonFail::Singular)?;
            self.core.stats.newton_iterations += 1;
            let mut sum = 0.0;
            for k in 0..3 {
                for (d, w) in self.st.dw[k].iter().zip(&self.wt.newton) {
                    sum += (d * w) * (d * w);
                }
            }
            let dyno = (sum / norm_n).sqrt();
            if !dyno.is_finite() {
                return Err(NewtonFail::Diverged);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dynold;
                self.ctl.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thqold).sqrt()
                };
                thqold = thq;
                if self.ctl.theta >= THETA_DIVERGING {
                    return Err(NewtonFail::Diverged);
                }
                self.ctl.faccon = self.ctl.theta / (1.0 - self.ctl.theta);
                let left = (nit - 1 - newt) as i32;
                let dyth = self.ctl.faccon * dyno * self.ctl.theta.powi(left) / self.fnewt;
                if dyth >= 1.0 {
                    let qnewt = dyth.clamp(SLOW_QNEWT_MIN, SLOW_QNEWT_MAX);
                    return Err(NewtonFail::Slow(
                        SLOW_SAFETY * qnewt.powf(-1.0 / (4.0 + left as f64)),
                    ));
                }
            }
            dynold = dyno.max(UROUND);
            for i in 0..self.core.n {
                let w0 = self.st.w[0][i] + self.st.dw[0][i];
                let w1 = self.st.w[1][i] + self.st.dw[1][i];
                let w2 = self.st.w[2][i] + self.st.dw[2][i];
                self.st.w[0][i] = w0;
                self.st.w[1][i] = w1;
                self.st.w[2][i] = w2;
                for k in 0..3 {
                    self.st.z[k][i] = T[k][0] * w0 + T[k][1] * w1 + T[k][2] * w2;
                }
            }
            if self.ctl.faccon * dyno <= self.fnewt {
                return Ok(newt);
            }
        }
        Err(NewtonFail::Diverged)
    }

    /// Solves the real system for dw[0] and the complex one for dw[1] + i dw[2], each
    /// with the frame transport of a kept matrix.
    fn solve_stages(&mut self) -> Result<(), Singular> {
        if self.mats.transport {
            // The stages' frames spread over the step (a wheel turns h omega in it, 0.4 rad
            // at 10 ms and 50 km/h); the matrix is carried to the middle stage's.
            for i in 0..self.core.n {
                self.mats.y_mid[i] = self.y[i] + self.st.z[1][i];
            }
        }
        let [d0, d1, d2] = &mut self.st.dw;
        if self.mats.transport {
            for d in [&mut *d0, &mut *d1, &mut *d2] {
                self.core
                    .prob
                    .transport(&self.mats.y_built, &self.mats.y_mid, d, Transport::Rows);
            }
        }
        self.mats.jac.solve(d0)?;
        self.mats.cjac.solve(d1, d2)?;
        if self.mats.transport {
            for d in [d0, d1, d2] {
                self.core.prob.transport(
                    &self.mats.y_built,
                    &self.mats.y_mid,
                    d,
                    Transport::Columns,
                );
            }
        }
        Ok(())
    }

    /// Solves E1 x = b (the real matrix), with the frame transport.
    pub(super) fn solve_real(&mut self, b: &mut [f64]) -> Result<(), Singular> {
        if self.mats.transport {
            self.core
                .prob
                .transport(&self.mats.y_built, &self.y, b, Transport::Rows);
        }
        self.mats.jac.solve(b)?;
        if self.mats.transport {
            self.core
                .prob
                .transport(&self.mats.y_built, &self.y, b, Transport::Columns);
        }
        Ok(())
    }

    /// What a failed Newton iteration does to the step (RADAU5, label 78 and the slow
    /// convergence branch): the factor for the step, or the error that ends the run.
    /// The Jacobian is evaluated anew unless it was evaluated for this very step.
    pub(super) fn newton_failed(
        &mut self,
        fail: &NewtonFail,
        failures: usize,
    ) -> Result<f64, SolverError> {
        if let NewtonFail::Singular(_) = fail {
            self.ctl.singular_in_row += 1;
        }
        // As RADAU5 ("UNEXPECTED STEP-REJECTION"): a Newton iteration that diverges or
        // converges too slowly only cuts the step (by at least 1 - SLOW_SAFETY), and the
        // step-size guard ends a step that cannot pass; IDA's ten failures per step ended
        // runs a few more cuts would have carried through (the coupling head's play).
        // Singular matrices in a row and non-finite residuals still end the run.
        let counted = matches!(fail, NewtonFail::NonFinite(_));
        let give_up = (counted && failures >= self.core.opts.max_convergence_failures)
            || self.ctl.singular_in_row >= MAX_SINGULAR;
        if give_up {
            return Err(match fail {
                NewtonFail::Singular(s) => SolverError::SingularMatrix {
                    t: self.core.t,
                    h: self.h,
                    detail: s.detail.clone(),
                },
                NewtonFail::NonFinite(eqs) => SolverError::NonFiniteResidual {
                    t: self.core.t,
                    equations: eqs.clone(),
                },
                NewtonFail::Diverged | NewtonFail::Slow(_) => SolverError::ConvergenceFailure {
                    t: self.core.t,
                    h: self.h,
                    failures,
                    worst: self.core.worst_components(&self.st.dw[0], &self.wt.newton),
                },
            });
        }
        if !self.mats.jac_fresh {
            self.mats.jac_valid = false;
            self.mats.slow_newton = true;
        }
        // A singular factorisation leaves no usable factors.
        if let NewtonFail::Singular(_) = fail {
            self.mats.h_factored = 0.0;
        }
        Ok(match fail {
            NewtonFail::Slow(f) => *f,
            _ => FAILURE_CUT,
        })
    }
}
