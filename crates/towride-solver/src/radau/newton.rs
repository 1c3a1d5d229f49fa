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
        let evaluated = !self.jac_valid;
        if evaluated {
            let cj = GAMMA / self.h;
            self.jeval
                .eval(
                    self.prob,
                    &mut self.jac,
                    self.t,
                    &self.y,
                    &self.yp,
                    cj,
                    self.h,
                    &self.ewt,
                    true,
                    &mut self.stats,
                )
                .map_err(NewtonFail::NonFinite)?;
            self.jac.keep_as_base(cj);
            if self.jeval.analytic && !self.jeval.yp_entries.is_empty() {
                self.jac.set_yp_part(&self.jeval.yp_entries);
            } else {
                // dF/dy' from a second evaluation at cj = 0 (a problem that does not
                // report it, or finite differences).
                self.jeval
                    .eval(
                        self.prob,
                        &mut self.jac,
                        self.t,
                        &self.y,
                        &self.yp,
                        0.0,
                        self.h,
                        &self.ewt,
                        false,
                        &mut self.stats,
                    )
                    .map_err(NewtonFail::NonFinite)?;
                self.jac.take_yp_part();
            }
            self.y_built.copy_from_slice(&self.y);
            self.jac_valid = true;
            self.jac_fresh = true;
            self.h_factored = 0.0;
        }
        if self.h_factored != self.h {
            self.h_factored = 0.0;
            let why = &mut self.stats.matrix_rebuilds;
            if !evaluated {
                // A kept Jacobian for a new step: J_y + s J_y' recombined from its parts.
                why.step_change += 1;
                self.stats.matrix_recombinations += 1;
            } else if self.slow_newton {
                why.convergence += 1;
            } else {
                why.invalid += 1;
            }
            let equilibrate = self.opts.scale_newton_matrix;
            self.jac.recombine(GAMMA / self.h);
            self.stats.lu_factorizations += 1;
            let done = self.jac.factor(&self.col_scale, equilibrate);
            self.stats.lu_entries = self.jac.lu_nnz().unwrap_or(0);
            done.map_err(NewtonFail::Singular)?;
            self.stats.complex_lu_factorizations += 1;
            let shift = Complex::new(ALPHA / self.h, BETA / self.h);
            self.cjac
                .factor(&self.jac, shift, &self.col_scale, equilibrate)
                .map_err(NewtonFail::Singular)?;
            self.h_factored = self.h;
        }
        Ok(())
    }

    /// Starting values: zero at the first step, else the collocation polynomial of the
    /// last step extrapolated (RADAU5 with STARTN = .FALSE.).
    pub(super) fn starting_values(&mut self) {
        if self.first {
            for k in 0..3 {
                self.z[k].fill(0.0);
                self.w[k].fill(0.0);
            }
            return;
        }
        let c3q = self.h / self.h_old;
        let cq = [C[0] * c3q, C[1] * c3q, c3q];
        let (c1m1, c2m1) = (C[0] - 1.0, C[1] - 1.0);
        for i in 0..self.n {
            let (a1, a2, a3) = (self.cont[1][i], self.cont[2][i], self.cont[3][i]);
            let mut zi = [0.0; 3];
            for k in 0..3 {
                zi[k] = cq[k] * (a1 + (cq[k] - c2m1) * (a2 + (cq[k] - c1m1) * a3));
                self.z[k][i] = zi[k];
            }
            for k in 0..3 {
                self.w[k][i] = TI[k][0] * zi[0] + TI[k][1] * zi[1] + TI[k][2] * zi[2];
            }
        }
    }

    /// Y'_k = (1/h) sum_j (A^-1)_kj Z_j into `yps`.
    pub(super) fn stage_derivative(&mut self, k: usize) {
        let a = self.ainv[k];
        let hinv = 1.0 / self.h;
        for i in 0..self.n {
            self.yps[i] = hinv * (a[0] * self.z[0][i] + a[1] * self.z[1][i] + a[2] * self.z[2][i]);
        }
    }

    /// The simplified Newton iteration; returns the iterations used.
    pub(super) fn newton(&mut self) -> Result<usize, NewtonFail> {
        let nit = self.opts.radau.newton_iters;
        self.faccon = self.faccon.max(UROUND).powf(FACCON_MEMORY);
        self.theta = self.opts.radau.jacobian_theta.abs();
        let (mut dynold, mut thqold) = (0.0, 0.0);
        let norm_n = (3 * self.n) as f64;
        for newt in 1..=nit {
            // Stage residuals G_k, transformed: dw_k = -sum_j TI_kj G_j.
            for k in 0..3 {
                self.dw[k].fill(0.0);
            }
            for j in 0..3 {
                for i in 0..self.n {
                    self.ys[i] = self.y[i] + self.z[j][i];
                }
                self.stage_derivative(j);
                let tj = self.t + C[j] * self.h;
                self.prob.residual(tj, &self.ys, &self.yps, &mut self.res);
                self.stats.residual_evals += 1;
                if let Some(bad) = self.non_finite_residual() {
                    return Err(NewtonFail::NonFinite(bad));
                }
                for k in 0..3 {
                    let c = TI[k][j];
                    for (d, r) in self.dw[k].iter_mut().zip(&self.res) {
                        *d -= c * r;
                    }
                }
            }
            self.solve_stages().map_err(NewtonFail::Singular)?;
            self.stats.newton_iterations += 1;
            let mut sum = 0.0;
            for k in 0..3 {
                for (d, w) in self.dw[k].iter().zip(&self.wt_newton) {
                    sum += (d * w) * (d * w);
                }
            }
            let dyno = (sum / norm_n).sqrt();
            if !dyno.is_finite() {
                return Err(NewtonFail::Diverged);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dynold;
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thqold).sqrt()
                };
                thqold = thq;
                if self.theta >= THETA_DIVERGING {
                    return Err(NewtonFail::Diverged);
                }
                self.faccon = self.theta / (1.0 - self.theta);
                let left = (nit - 1 - newt) as i32;
                let dyth = self.faccon * dyno * self.theta.powi(left) / self.fnewt;
                if dyth >= 1.0 {
                    let qnewt = dyth.clamp(SLOW_QNEWT_MIN, SLOW_QNEWT_MAX);
                    return Err(NewtonFail::Slow(
                        SLOW_SAFETY * qnewt.powf(-1.0 / (4.0 + left as f64)),
                    ));
                }
            }
            dynold = dyno.max(UROUND);
            for i in 0..self.n {
                let w0 = self.w[0][i] + self.dw[0][i];
                let w1 = self.w[1][i] + self.dw[1][i];
                let w2 = self.w[2][i] + self.dw[2][i];
                self.w[0][i] = w0;
                self.w[1][i] = w1;
                self.w[2][i] = w2;
                for k in 0..3 {
                    self.z[k][i] = T[k][0] * w0 + T[k][1] * w1 + T[k][2] * w2;
                }
            }
            if self.faccon * dyno <= self.fnewt {
                return Ok(newt);
            }
        }
        Err(NewtonFail::Diverged)
    }

    /// Solves the real system for dw[0] and the complex one for dw[1] + i dw[2], each
    /// with the frame transport of a kept matrix.
    fn solve_stages(&mut self) -> Result<(), Singular> {
        if self.transport {
            // The stages' frames spread over the step (a wheel turns h omega in it, 0.4 rad
            // at 10 ms and 50 km/h); the matrix is carried to the middle stage's.
            for i in 0..self.n {
                self.y_mid[i] = self.y[i] + self.z[1][i];
            }
        }
        let [d0, d1, d2] = &mut self.dw;
        if self.transport {
            for d in [&mut *d0, &mut *d1, &mut *d2] {
                self.prob
                    .transport(&self.y_built, &self.y_mid, d, Transport::Rows);
            }
        }
        self.jac.solve(d0)?;
        self.cjac.solve(d1, d2)?;
        if self.transport {
            for d in [d0, d1, d2] {
                self.prob
                    .transport(&self.y_built, &self.y_mid, d, Transport::Columns);
            }
        }
        Ok(())
    }

    /// Solves E1 x = b (the real matrix), with the frame transport.
    pub(super) fn solve_real(&mut self, b: &mut [f64]) -> Result<(), Singular> {
        if self.transport {
            self.prob
                .transport(&self.y_built, &self.y, b, Transport::Rows);
        }
        self.jac.solve(b)?;
        if self.transport {
            self.prob
                .transport(&self.y_built, &self.y, b, Transport::Columns);
        }
        Ok(())
    }

    pub(super) fn non_finite_residual(&self) -> Option<String> {
        if self.res.iter().all(|v| v.is_finite()) {
            return None;
        }
        let bad: Vec<String> = (0..self.n)
            .filter(|&i| !self.res[i].is_finite())
            .take(5)
            .map(|i| self.prob.eq_name(i))
            .collect();
        Some(bad.join(", "))
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
            self.singular_in_row += 1;
        }
        let give_up =
            failures >= self.opts.max_convergence_failures || self.singular_in_row >= MAX_SINGULAR;
        if give_up {
            return Err(match fail {
                NewtonFail::Singular(s) => SolverError::SingularMatrix {
                    t: self.t,
                    h: self.h,
                    detail: s.detail.clone(),
                },
                NewtonFail::NonFinite(eqs) => SolverError::NonFiniteResidual {
                    t: self.t,
                    equations: eqs.clone(),
                },
                NewtonFail::Diverged | NewtonFail::Slow(_) => SolverError::ConvergenceFailure {
                    t: self.t,
                    h: self.h,
                    failures,
                    worst: self.worst_components(&self.dw[0], &self.wt_newton),
                },
            });
        }
        if !self.jac_fresh {
            self.jac_valid = false;
            self.slow_newton = true;
        }
        // A singular factorisation leaves no usable factors.
        if let NewtonFail::Singular(_) = fail {
            self.h_factored = 0.0;
        }
        Ok(match fail {
            NewtonFail::Slow(f) => *f,
            _ => FAILURE_CUT,
        })
    }
}
