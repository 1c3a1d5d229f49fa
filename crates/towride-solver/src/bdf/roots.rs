//! Event location: sign changes of the problem's event functions g(t, y, y') between
//! steps, refined on the interpolating polynomial with the Illinois variant of regula
//! falsi (as IDA's IDARcheck3 and IDARootfind).

use super::{Advance, Bdf, UROUND};
use crate::error::SolverError;
use crate::problem::DaeProblem;

impl<P: DaeProblem + ?Sized> Bdf<'_, P> {
    /// Looks for a sign change of the event functions over (t_lo, tn] and locates it on
    /// the interpolant with the Illinois method (as IDA's IDARcheck3).
    pub(super) fn check_roots(&mut self) -> Result<Option<Advance>, SolverError> {
        let nr = self.g_lo.len();
        if nr == 0 || !self.started || self.tn <= self.t_lo {
            return Ok(None);
        }
        let (mut y, mut yp) = (vec![0.0; self.n], vec![0.0; self.n]);
        let mut g_hi = std::mem::take(&mut self.g_hi);
        self.interpolate(self.tn, &mut y, &mut yp);
        self.prob.roots(self.tn, &y, &yp, &mut g_hi);
        self.stats.root_evals += 1;
        let changed = |glo: &[f64], ghi: &[f64]| -> Option<usize> {
            let mut best: Option<(usize, f64)> = None;
            for i in 0..glo.len() {
                if glo[i] != 0.0 && (ghi[i] == 0.0 || glo[i].signum() != ghi[i].signum()) {
                    let frac = (glo[i] / (glo[i] - ghi[i])).abs();
                    if best.is_none_or(|(_, f)| frac < f) {
                        best = Some((i, frac));
                    }
                }
            }
            best.map(|b| b.0)
        };
        let Some(_) = changed(&self.g_lo, &g_hi) else {
            self.t_lo = self.tn;
            self.g_lo.copy_from_slice(&g_hi);
            self.g_hi = g_hi;
            return Ok(None);
        };
        let ttol = 100.0 * UROUND * (self.tn.abs() + self.hh.abs());
        let (mut tlo, mut thi) = (self.t_lo, self.tn);
        let mut glo = self.g_lo.clone();
        let mut ghi = g_hi.clone();
        let mut gmid = vec![0.0; nr];
        let mut side = 0i32;
        let mut idx = changed(&glo, &ghi).expect("sign change found above");
        for _ in 0..200 {
            if thi - tlo <= ttol {
                break;
            }
            let (a, b) = (glo[idx], ghi[idx]);
            let (mut wa, mut wb) = (1.0, 1.0);
            if side == 1 {
                wb = 0.5;
            } else if side == -1 {
                wa = 0.5;
            }
            let mut tmid = thi - (thi - tlo) * (wb * b) / (wb * b - wa * a);
            let margin = 0.5 * ttol;
            tmid = tmid.clamp(tlo + margin, thi - margin);
            self.interpolate(tmid, &mut y, &mut yp);
            self.prob.roots(tmid, &y, &yp, &mut gmid);
            self.stats.root_evals += 1;
            if let Some(i) = changed(&glo, &gmid) {
                thi = tmid;
                ghi.copy_from_slice(&gmid);
                idx = i;
                side = if side == 1 { 2 } else { 1 };
            } else {
                tlo = tmid;
                glo.copy_from_slice(&gmid);
                side = if side == -1 { -2 } else { -1 };
            }
        }
        // Continue the next search just past the root.
        self.t_lo = thi;
        self.g_lo.copy_from_slice(&ghi);
        for g in self.g_lo.iter_mut() {
            if *g == 0.0 {
                *g = f64::MIN_POSITIVE; // a root exactly at t_lo is not reported twice
            }
        }
        self.g_hi = g_hi;
        Ok(Some(Advance::Root { t: thi, index: idx }))
    }
}
