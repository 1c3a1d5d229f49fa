//! Local error test and the choice of the next order and step (IDATestError,
//! IDACompleteStep).

use super::{Bdf, ERR_BIAS, ETA_LOW, ETA_MAX, ETA_MIN, ETA_MIN_FX};
use crate::method::wrms;
use crate::problem::DaeProblem;

impl<P: DaeProblem + ?Sized> Bdf<'_, P> {
    /// Local error estimates at orders k, k-1, k-2 and the order to use on a retry
    /// (IDATestError). Returns ||E_k|| in the error-test weights.
    pub(super) fn test_error(&mut self) -> f64 {
        let ctl = &mut self.ctl;
        let (h, w) = (&self.hist, &mut self.work);
        let kk = ctl.kk;
        let enorm_k = wrms(&w.ee, &self.wt.err);
        ctl.err_k = h.sigma[kk] * enorm_k;
        let terr_k = (kk as f64 + 1.0) * ctl.err_k;
        ctl.knew = kk;
        if kk > 1 {
            let d = &mut w.scratch;
            for ((v, p), e) in d.iter_mut().zip(&h.phi[kk]).zip(&w.ee) {
                *v = p + e;
            }
            let enorm_km1 = wrms(d, &self.wt.err);
            ctl.err_km1 = h.sigma[kk - 1] * enorm_km1;
            let terr_km1 = kk as f64 * ctl.err_km1;
            if kk > 2 {
                for (v, p) in d.iter_mut().zip(&h.phi[kk - 1]) {
                    *v += p;
                }
                let enorm_km2 = wrms(d, &self.wt.err);
                let err_km2 = h.sigma[kk - 2] * enorm_km2;
                let terr_km2 = (kk as f64 - 1.0) * err_km2;
                if terr_km1.max(terr_km2) <= terr_k {
                    ctl.knew = kk - 1;
                }
            } else if terr_km1 <= 0.5 * terr_k {
                ctl.knew = kk - 1;
            }
        }
        enorm_k
    }

    /// Accepts the step: statistics, next order and step size, history update
    /// (IDACompleteStep).
    pub(super) fn complete_step(&mut self) {
        let stald_limited = if self.core.opts.stability_limit_detection {
            self.stald_record();
            self.stald_limited()
        } else {
            false
        };
        let ctl = &mut self.ctl;
        self.core
            .book_step(ctl.hh, ctl.kk, &self.work.ee, &self.wt.err);
        let kdiff = ctl.kk as isize - ctl.kused as isize;
        ctl.kused = ctl.kk;
        let maxord = self.core.opts.max_order;
        if ctl.knew + 1 == ctl.kk || ctl.kk == maxord {
            ctl.phase = 1;
        }
        let hmax = self.core.opts.h_max;
        if ctl.phase == 0 {
            if self.core.stats.steps > 1 {
                ctl.kk += 1;
                ctl.hh = (ETA_MAX * ctl.hh).min(hmax);
            }
        } else {
            #[derive(PartialEq)]
            enum Action {
                Lower,
                Maintain,
                Raise,
            }
            let kk = ctl.kk;
            let mut err_kp1 = 0.0;
            let action = if ctl.knew + 1 == kk {
                Action::Lower
            } else if kk == maxord || kk + 1 >= ctl.ns || kdiff == 1 {
                Action::Maintain
            } else {
                let d = &mut self.work.scratch;
                for ((v, e), p) in d.iter_mut().zip(&self.work.ee).zip(&self.hist.phi[kk + 1]) {
                    *v = e - p;
                }
                err_kp1 = wrms(d, &self.wt.err) / (kk as f64 + 2.0);
                // IDA compares the terms T(j) = (j+1) err_j, not the scaled errors
                // (IDACompleteStep: terr_km1 = k err_km1, terr_k = (k+1) err_k,
                // terr_kp1 = (k+2) err_kp1; DASSL's TERKM1/TERK/TERKP1 likewise).
                let terr_k = (kk as f64 + 1.0) * ctl.err_k;
                let terr_kp1 = (kk as f64 + 2.0) * err_kp1;
                if kk == 1 {
                    if terr_kp1 >= 0.5 * terr_k {
                        Action::Maintain
                    } else {
                        Action::Raise
                    }
                } else if kk as f64 * ctl.err_km1 <= terr_k.min(terr_kp1) {
                    Action::Lower
                } else if terr_kp1 >= terr_k {
                    Action::Maintain
                } else {
                    Action::Raise
                }
            };
            // CVODE's cvBDFStab (`bdf/stald.rs`): unless the error estimates already lower
            // the order, STALD may find the step stability-limited and lower it; the step
            // then follows the order-(k-1) estimate, as CVODE takes etaqm1.
            let action = if stald_limited && action != Action::Lower {
                self.core.stats.stability_order_reductions += 1;
                Action::Lower
            } else {
                action
            };
            let err_knew = match action {
                Action::Raise => {
                    ctl.kk += 1;
                    err_kp1
                }
                Action::Lower => {
                    ctl.kk -= 1;
                    ctl.err_km1
                }
                Action::Maintain => ctl.err_k,
            };
            let rr = (2.0 * err_knew + ERR_BIAS).powf(-1.0 / (ctl.kk as f64 + 1.0));
            // The step is kept unless it may grow by eta_fixed_max (IDA's ETA_MAX_FX,
            // IDASetEtaFixedStepBounds) or must shrink; growth is capped at ETA_MAX.
            if rr >= self.core.opts.eta_fixed_max {
                ctl.hh = (rr.min(ETA_MAX) * ctl.hh).min(hmax);
            } else if rr <= ETA_MIN_FX {
                ctl.hh *= rr.clamp(ETA_MIN, ETA_LOW);
            }
        }
        let ku = ctl.kused;
        let phi = &mut self.hist.phi;
        if ku < maxord {
            phi[ku + 1].copy_from_slice(&self.work.ee);
        }
        for (p, e) in phi[ku].iter_mut().zip(&self.work.ee) {
            *p += e;
        }
        for j in (0..ku).rev() {
            let (lo, hi) = phi.split_at_mut(j + 1);
            for (a, b) in lo[j].iter_mut().zip(&hi[0]) {
                *a += b;
            }
        }
        self.set_ewt();
    }
}
