//! Local error test and the choice of the next order and step (IDATestError,
//! IDACompleteStep).

use super::Bdf;
use crate::problem::DaeProblem;

impl<P: DaeProblem + ?Sized> Bdf<'_, P> {
    /// Local error estimates at orders k, k-1, k-2 and the order to use on a retry
    /// (IDATestError). Returns ||E_k|| in the error-test weights.
    pub(super) fn test_error(&mut self) -> f64 {
        let kk = self.kk;
        let enorm_k = self.wrms(&self.ee, &self.wt_err);
        self.err_k = self.sigma[kk] * enorm_k;
        let terr_k = (kk as f64 + 1.0) * self.err_k;
        self.knew = kk;
        if kk > 1 {
            let mut d = std::mem::take(&mut self.scratch);
            for ((v, p), e) in d.iter_mut().zip(&self.phi[kk]).zip(&self.ee) {
                *v = p + e;
            }
            let enorm_km1 = self.wrms(&d, &self.wt_err);
            self.err_km1 = self.sigma[kk - 1] * enorm_km1;
            let terr_km1 = kk as f64 * self.err_km1;
            if kk > 2 {
                for (v, p) in d.iter_mut().zip(&self.phi[kk - 1]) {
                    *v += p;
                }
                let enorm_km2 = self.wrms(&d, &self.wt_err);
                let err_km2 = self.sigma[kk - 2] * enorm_km2;
                let terr_km2 = (kk as f64 - 1.0) * err_km2;
                if terr_km1.max(terr_km2) <= terr_k {
                    self.knew = kk - 1;
                }
            } else if terr_km1 <= 0.5 * terr_k {
                self.knew = kk - 1;
            }
            self.scratch = d;
        }
        enorm_k
    }

    /// Accepts the step: statistics, next order and step size, history update
    /// (IDACompleteStep).
    pub(super) fn complete_step(&mut self) {
        self.stats.steps += 1;
        let kdiff = self.kk as isize - self.kused as isize;
        self.kused = self.kk;
        self.hused = self.hh;
        self.stats.last_order = self.kk;
        self.stats.last_step = self.hh;
        self.stats.order_counts[self.kk - 1] += 1;
        if self.opts.record_steps {
            self.stats
                .step_history
                .push((self.tn, self.hused, self.kused));
        }
        let maxord = self.opts.max_order;
        if self.knew + 1 == self.kk || self.kk == maxord {
            self.phase = 1;
        }
        let hmax = self.opts.h_max;
        if self.phase == 0 {
            if self.stats.steps > 1 {
                self.kk += 1;
                self.hh = (2.0 * self.hh).min(hmax);
            }
        } else {
            #[derive(PartialEq)]
            enum Action {
                Lower,
                Maintain,
                Raise,
            }
            let kk = self.kk;
            let mut err_kp1 = 0.0;
            let action = if self.knew + 1 == kk {
                Action::Lower
            } else if kk == maxord || kk + 1 >= self.ns || kdiff == 1 {
                Action::Maintain
            } else {
                let mut d = std::mem::take(&mut self.scratch);
                for ((v, e), p) in d.iter_mut().zip(&self.ee).zip(&self.phi[kk + 1]) {
                    *v = e - p;
                }
                err_kp1 = self.wrms(&d, &self.wt_err) / (kk as f64 + 2.0);
                self.scratch = d;
                // IDA compares the terms T(j) = (j+1) err_j, not the scaled errors
                // (IDACompleteStep: terr_km1 = k err_km1, terr_k = (k+1) err_k,
                // terr_kp1 = (k+2) err_kp1; DASSL's TERKM1/TERK/TERKP1 likewise).
                let terr_k = (kk as f64 + 1.0) * self.err_k;
                let terr_kp1 = (kk as f64 + 2.0) * err_kp1;
                if kk == 1 {
                    if terr_kp1 >= 0.5 * terr_k {
                        Action::Maintain
                    } else {
                        Action::Raise
                    }
                } else if kk as f64 * self.err_km1 <= terr_k.min(terr_kp1) {
                    Action::Lower
                } else if terr_kp1 >= terr_k {
                    Action::Maintain
                } else {
                    Action::Raise
                }
            };
            let err_knew = match action {
                Action::Raise => {
                    self.kk += 1;
                    err_kp1
                }
                Action::Lower => {
                    self.kk -= 1;
                    self.err_km1
                }
                Action::Maintain => self.err_k,
            };
            let rr = (2.0 * err_knew + 0.0001).powf(-1.0 / (self.kk as f64 + 1.0));
            // The step is kept unless it may grow by eta_fixed_max (IDA's
            // IDASetEtaFixedStepBounds) or must shrink; growth is capped at 2.
            if rr >= self.opts.eta_fixed_max {
                self.hh = (rr.min(2.0) * self.hh).min(hmax);
            } else if rr <= 1.0 {
                self.hh *= rr.clamp(0.5, 0.9);
            }
        }
        let ku = self.kused;
        if ku < maxord {
            self.phi[ku + 1].copy_from_slice(&self.ee);
        }
        for (p, e) in self.phi[ku].iter_mut().zip(&self.ee) {
            *p += e;
        }
        for j in (0..ku).rev() {
            let (lo, hi) = self.phi.split_at_mut(j + 1);
            for (a, b) in lo[j].iter_mut().zip(&hi[0]) {
                *a += b;
            }
        }
        self.set_ewt();
    }
}
